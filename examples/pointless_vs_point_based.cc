// Example 2: the pointless global BA (paper eq. 5) against a classical point-based BA, on the
// same synthetic block and from the same initial poses.
//
// Point-based BA: unknowns are every pose and every 3D point (6 per image + 3 per point).
// Pointless BA: unknowns are every pose and one similarity per relative motion (7 each); the
// points only appear inside each motion's local BA, which leaves behind its local poses x0_s
// and its camera reduced matrix h_s = V_s^T D_s^2 V_s. The global cost is
//     E = sum_s | D_s V_s (d_s(X) - x0_s) |^2          (paper eq. 5)
// with d_s(X) the motion's local poses predicted from the global poses X (eq. 4).
//
// Two kinds of motions are compared:
//   * the paper's triplets (three views each, their own converged local BA): each track is
//     cut into three-view pieces and an observation counts in every triplet that uses it, so
//     the sum of the h_s is only an approximation of the point-based system;
//   * pgba's default whole-track motions: every track lies whole in exactly one motion and
//     every observation has weight 1, so sum_s h_s IS the point-based reduced camera system
//     (modules/local_hessian/whole_track_motions.h) and the poses agree with the point-based
//     BA's up to what the points' non-linearity adds.
//
// Run: build/bin/example_pointless_vs_point_based   (prints "key: value" lines)
#include <cstdio>

#include "examples/example_common.h"
#include "synthetic/synthetic_scene.h"

using namespace pgba;
using namespace pgba::examples;

int main() {
  // A ring of 48 views (the orbit scenario), 0.5 px noise, no outliers.
  SyntheticOptions so;
  so.scenario = SyntheticScenario::kOrbit;
  so.num_images = 48;
  so.num_points = 12000;
  const SyntheticScene scene = GenerateSyntheticScene(so);
  const Reconstruction& tracks = scene.input;  // observations and cameras; poses unknown
  Poses truth;
  for (const auto& [id, im] : scene.gt.images) truth[id] = im.pose;
  // Start: rotations 0.1 deg off (2 px at this focal), centres 0.1% of the ring's size,
  // about what rotation and translation averaging leave on such a ring.
  const Poses initial = Perturbed(truth, 0.1, 0.001 * scene.extent, 7);
  std::printf("images: %zu\npoints: %zu\n", truth.size(), tracks.points3D.size());
  std::printf("init_rel_rot_err_deg: %.5f\n", RelRotErrDeg(initial, truth));

  // 1. Point-based BA: 6 unknowns per image + 3 per point.
  size_t num_points = 0;
  const Poses point_based = PointBasedBA(tracks, initial, &num_points);
  const double err_pb = RelRotErrDeg(point_based, truth);
  std::printf("pointbased_params: %zu\n", 6 * truth.size() + 3 * num_points);
  std::printf("pointbased_rel_rot_err_deg: %.5f\n", err_pb);

  // 2. The paper's pointless BA over triplets, with its defaults (Hessian weights, Huber and
  //    IRLS on the motions' fitting errors, one linearisation).
  //    A triplet knows nothing of the global solution: its local BA starts from its own
  //    estimate and converges to its own optimum near the truth. We start it from the true
  //    poses, which leads to that same optimum (observations are noisy, so x0_s is not the
  //    truth); the global BA starts from `initial` as the other methods do.
  const std::vector<LocalMotion> triplets = RingTriplets(tracks, truth, /*closed=*/true);
  const LocalHessianResult th = TripletHessians(tracks, triplets);
  const GlobalBAResult tr = PointlessGlobalBA(initial, triplets, th.hessians, PaperTripletGlobalBAOptions());
  const double err_tr = RelRotErrDeg(tr.poses, truth);
  std::printf("triplets: %d\n", th.num_ok());
  std::printf("triplets_params: %d\n", tr.summary.num_params);
  std::printf("triplets_rel_rot_err_deg: %.5f\n", err_tr);
  std::printf("triplets_ratio_to_pointbased: %.3f\n", err_tr / err_pb);

  // Eq. 5 written out for each triplet at the solution: the similarity d_s maps the global
  // poses into the triplet's frame (c = s R C + t, r = R_cam R^T, eq. 4), the deviation from
  // x0_s is taken in h's chart [c - c0, Log(r0^T r)], and D_s V_s whitens it. Were the
  // triplets' models exact and independent, each |r_s|^2 would be about the noise sigma^2
  // (times the observation weight) on each of its 11 informative directions; it is less,
  // since the solution lies between the triplets that share views.
  std::vector<double> misfit;
  for (size_t s = 0; s < triplets.size(); ++s) {
    const LocalHessian& lh = th.hessians[s];
    if (lh.status != LocalHessianStatus::kOk || tr.irls_weights[s] <= 0) continue;
    Eigen::VectorXd dx(18);
    for (int k = 0; k < 3; ++k) {
      const Pose x = tr.similarities[s].Apply(tr.poses.at(lh.image_ids[k]));
      dx.segment<3>(6 * k) = x.C() - lh.local_poses[k].C();
      dx.segment<3>(6 * k + 3) = LogSO3(lh.local_poses[k].R().transpose() * x.R());
    }
    Eigen::MatrixXd V;
    Eigen::VectorXd D;
    lh.Factor(&V, &D);  // W = diag(D) V, paper eq. 5
    const Eigen::VectorXd r = D.asDiagonal() * (V * dx);  // eq. 5's residual, 18 rows
    misfit.push_back(r.squaredNorm() / (11.0 * so.noise_px * so.noise_px * lh.observation_weight));
  }
  std::nth_element(misfit.begin(), misfit.begin() + misfit.size() / 2, misfit.end());
  std::printf("triplets_eq5_misfit_median: %.3f\n", misfit[misfit.size() / 2]);

  // 3. pgba's default pointless BA over whole-track motions (example_common.h says why).
  int params = 0;
  const Poses pointless = WholeTrackPointlessBA(tracks, initial, &params);
  const double err_wt = RelRotErrDeg(pointless, truth);
  std::printf("pointless_params: %d\n", params);
  std::printf("pointless_rel_rot_err_deg: %.5f\n", err_wt);
  std::printf("pointless_ratio_to_pointbased: %.3f\n", err_wt / err_pb);
  // How far the pointless poses are from the point-based ones, against how far both are from
  // the truth: the two adjustments solve the same problem, so this is much smaller.
  std::printf("pointless_vs_pointbased_rel_rot_deg: %.5f\n", RelRotErrDeg(pointless, point_based));
  return 0;
}
