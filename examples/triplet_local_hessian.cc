// Example 1: one triplet's local bundle adjustment and its 18x18 camera reduced matrix.
//
// The pointless global BA never sees a 3D point. Everything it knows about a relative motion
// (here three views, the paper's triplets) is the motion's local poses x0 and the matrix h
// that its local BA leaves behind (paper eqs. 1-3). This program builds one triplet on a
// synthetic ring, runs its local BA and looks at h:
//   * h is 18x18 (6 unknowns per view: centre c and small rotation omega, R = R0 Exp(omega));
//   * h has exactly 7 zero eigenvalues: a similarity of the local frame (3 translation,
//     3 rotation, 1 scale) moves poses and points together and no reprojection changes;
//   * those 7 directions are the similarity generators acting on the poses;
//   * the weak prior that "observes" the extrinsics (the paper's gauge fixing) lifts exactly
//     these 7 eigenvalues to mu and leaves the 11 informative ones untouched.
//
// Run: build/bin/example_triplet_local_hessian   (prints "key: value" lines)
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>

#include "local_hessian/local_bundle.h"
#include "local_hessian/reduced_camera_matrix.h"
#include "pgba/geometry/rotation.h"
#include "synthetic/synthetic_scene.h"

using namespace pgba;

int main() {
  // A ring of 36 views around an object, 0.5 px Gaussian noise per coordinate, no outliers.
  SyntheticOptions so;
  so.scenario = SyntheticScenario::kOrbit;
  so.num_images = 36;
  so.num_points = 8000;  // twice the scenario's density: a few hundred points per triplet
  so.noise_px = 0.5;
  const SyntheticScene scene = GenerateSyntheticScene(so);
  const Reconstruction& tracks = scene.gt;  // true poses; observations are the noisy ones

  // The triplet: three neighbouring views. Its local frame is arbitrary (a triplet BA knows
  // nothing of the global frame), so we put its poses in a frame of our own: the true poses
  // mapped by a similarity with scale 0.2. The local BA must not care.
  LocalMotion motion;
  motion.image_ids = {1, 2, 3};
  Sim3 to_local;
  to_local.s = 0.2;
  to_local.R = ExpSO3(Eigen::Vector3d(0.3, -0.2, 0.5));
  to_local.t = Eigen::Vector3d(1.0, 2.0, -0.5);
  for (uint32_t id : motion.image_ids) motion.local_poses.push_back(to_local.Apply(tracks.images.at(id).pose));
  // Its tracks: every point seen by at least two of the three views.
  std::set<uint64_t> ids;
  for (const auto& [pid, pt] : tracks.points3D) {
    int seen = 0;
    for (const TrackElement& el : pt.track) seen += el.image_id <= 3;
    if (seen >= 2) ids.insert(pid);
  }
  motion.track_ids.assign(ids.begin(), ids.end());

  // Paper eq. 1: the local BA over 3 poses and M points, Huber 1 px, every observation
  // weighted gamma / M = Q / (M + Q) (the paper's attenuation, Q = 10: a triplet weighs like
  // ~10 points whatever M, so that triplets with many points do not dominate).
  LocalHessianOptions options = PaperTripletLocalHessianOptions();
  LocalBundleProblem problem;
  if (BuildLocalBundleProblem(tracks, motion, options, &problem) != LocalHessianStatus::kOk) return 1;
  // Converged: x0 is the triplet's optimum.
  SolveLocalBundle(LocalBundleSolverOptions(/*max_iterations=*/20), &problem);
  const int M = static_cast<int>(problem.points.size());
  const int n_obs = static_cast<int>(problem.observations.size());
  std::printf("points: %d\nobservations: %d\n", M, n_obs);
  // Residual RMS after the BA. Its expectation is known: 2 n_obs residuals minus the
  // (3 M + 18 - 7) unknowns that fit the noise (7: the gauge fits none), each sigma^2.
  std::printf("rms_px: %.4f\n", RmsReprojectionPx(problem));
  std::printf("rms_px_expected: %.4f\n", so.noise_px * std::sqrt((2.0 * n_obs - (3.0 * M + 11.0)) / n_obs));
  std::printf("observation_weight: %.5f\n", problem.observation_weight);

  // Paper eqs. 2-3: normal equations H = J^T J of poses and points, then the Schur
  // complement on the points, h = H_cc - H_cp H_pp^-1 H_pc (one 3x3 H_pp block per point).
  const ReducedCameraSystem rcs = ReducedCameraMatrix(problem);
  const Eigen::MatrixXd& h = rcs.h;
  std::printf("h_size: %dx%d\n", static_cast<int>(h.rows()), static_cast<int>(h.cols()));
  std::printf("h_symmetry_error: %.2e\n", (h - h.transpose()).norm() / h.norm());

  // Eigenvalues in the chart [c / L, omega], L the median point depth: centres are then
  // measured as angles seen from the scene, like rotations, so that the eigenvalues of the
  // two kinds compare (in [c, omega] they would depend on the local frame's scale 0.2).
  const double L = MedianDepth(problem);
  Eigen::VectorXd chart = Eigen::VectorXd::Ones(18);
  for (int k = 0; k < 3; ++k) chart.segment<3>(6 * k).setConstant(L);
  const Eigen::MatrixXd hs = chart.asDiagonal() * h * chart.asDiagonal();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(hs);
  const Eigen::VectorXd lambda = eig.eigenvalues();  // ascending
  const double lmax = lambda(17);
  std::printf("eigenvalues_relative:");
  for (int i = 0; i < 18; ++i) std::printf(" %.3e", lambda(i) / lmax);
  std::printf("\n");
  // "Near zero": below 1e-12 of the largest, i.e. rounding of a 1e9/px^2-scale matrix.
  int near_zero = 0;
  for (int i = 0; i < 18; ++i) near_zero += std::abs(lambda(i)) < 1e-12 * lmax;
  std::printf("near_zero_eigenvalues: %d\n", near_zero);
  // The weakest informative direction against the strongest: how anisotropic a triplet's
  // information is (the reason a scalar weight per motion, Aver_BA, loses accuracy).
  std::printf("informative_eigenvalue_ratio: %.3e\n", lambda(7) / lmax);

  // The gauge directions: the infinitesimal similarities acting on the three poses
  // (SimilarityGenerators, in the same chart). h must annihilate them...
  const Eigen::MatrixXd G = SimilarityGenerators(problem.poses, L);
  double worst = 0.0;
  for (int j = 0; j < 7; ++j) worst = std::max(worst, (hs * G.col(j)).norm() / (lmax * G.col(j).norm()));
  std::printf("gauge_residual: %.2e\n", worst);
  // ...and span exactly h's null space: the largest principal angle between span(G) and the
  // 7 eigenvectors of the smallest eigenvalues (sine of it; 0 = same subspace).
  const Eigen::MatrixXd Q = Eigen::HouseholderQR<Eigen::MatrixXd>(G).householderQ() * Eigen::MatrixXd::Identity(18, 7);
  const Eigen::MatrixXd N = eig.eigenvectors().leftCols(7);
  const Eigen::JacobiSVD<Eigen::MatrixXd> cosines(Q.transpose() * N);
  std::printf("gauge_subspace_sin: %.2e\n", std::sqrt(std::max(0.0, 1.0 - std::pow(cosines.singularValues()(6), 2))));

  // The prior (paper: "all three extrinsics treated as observed"). Without it the global BA
  // cannot determine each triplet's similarity (the h_s do not see it) and stalls. pgba puts
  // mu = 1e-3 x lambda_max on the 7 gauge directions only, in the same scale-aware chart.
  const GaugePrior prior = ComputeGaugePrior(h, problem.poses, L, options);
  std::printf("prior_mu_relative: %.3e\n", prior.mu / lmax);
  const Eigen::MatrixXd hp = chart.asDiagonal() * (h + prior.P) * chart.asDiagonal();
  const Eigen::VectorXd lambda_p = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(hp).eigenvalues();
  // Expected: the 11 informative eigenvalues unchanged, and 7 new ones equal to mu.
  Eigen::VectorXd expected(18);
  expected << lambda.tail(11), Eigen::VectorXd::Constant(7, prior.mu);
  std::sort(expected.data(), expected.data() + 18);
  std::printf("prior_eigenvalue_error: %.2e\n", ((lambda_p - expected).array() / expected.array()).abs().maxCoeff());
  int at_mu = 0;
  for (int i = 0; i < 18; ++i) at_mu += std::abs(lambda_p(i) - prior.mu) < 1e-9 * prior.mu;
  std::printf("eigenvalues_at_mu: %d\n", at_mu);

  // Paper eq. 5 uses h through h = V^T D^2 V: the global residual of this triplet is
  // D V (x - x0), an 18-vector whose squared norm is (x - x0)^T h (x - x0).
  Eigen::MatrixXd V;
  Eigen::VectorXd D;
  DecomposeReducedMatrix(h + prior.P, &V, &D);
  const Eigen::MatrixXd W = D.asDiagonal() * V;
  std::printf("factor_error: %.2e\n", (W.transpose() * W - (h + prior.P)).norm() / h.norm());

  return 0;
}
