#include "modules/local_hessian/local_hessian.h"

#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <Eigen/Cholesky>

#include <algorithm>
#include <memory>

#include "modules/local_hessian/local_bundle.h"
#include "modules/local_hessian/reduced_camera_matrix.h"
#include "pgba/util/logging.h"

namespace pgba {

const char* LocalHessianStatusName(LocalHessianStatus status) {
  switch (status) {
    case LocalHessianStatus::kOk:
      return "ok";
    case LocalHessianStatus::kInvalidInput:
      return "invalid_input";
    case LocalHessianStatus::kTooFewPoints:
      return "too_few_points";
    case LocalHessianStatus::kSolverFailure:
      return "solver_failure";
    case LocalHessianStatus::kNonFinite:
      return "non_finite";
    case LocalHessianStatus::kIllConditioned:
      return "ill_conditioned";
  }
  return "unknown";
}

nlohmann::json LocalHessianStatusCounts(const LocalHessianResult& result) {
  nlohmann::json j = nlohmann::json::object();
  for (int s = 0; s < kNumLocalHessianStatus; ++s)
    j[LocalHessianStatusName(static_cast<LocalHessianStatus>(s))] = result.status_counts[s];
  return j;
}

LocalHessian ComputeLocalHessian(const Reconstruction& tracks, const LocalMotion& motion, int motion_index,
                                 const LocalHessianOptions& options, const ObservationShares* shares,
                                 const FreeIntrinsics* free) {
  LocalHessian out;
  out.motion_index = motion_index;
  out.image_ids = motion.image_ids;
  out.local_poses = motion.local_poses;

  LocalBundleProblem problem;
  out.status = BuildLocalBundleProblem(tracks, motion, options, &problem, shares, free);
  if (out.status != LocalHessianStatus::kOk) return out;
  out.num_points = static_cast<int>(problem.points.size());
  out.num_observations = static_cast<int>(problem.observations.size());
  double mean_share = 0.0;
  for (const LocalObservation& o : problem.observations) mean_share += o.weight;
  out.observation_weight = problem.observation_weight * mean_share / std::max<size_t>(1, problem.observations.size());

  GaugePrior input_prior;
  if (options.prior_placement == PriorPlacement::kLocalBAAndHessian) {
    // The extrinsics observed at their input values, with mu from h at the input.
    const ReducedCameraSystem h_in = ReducedCameraMatrix(problem);
    const int n = 6 * problem.num_views();  // the pose prior of the local BA: pose rows only
    input_prior = ComputeGaugePrior(h_in.h, problem.poses, MedianDepth(problem), options);
    problem.prior = input_prior.P.topLeftCorner(n, n);
  }
  if (!SolveLocalBundle(options.solver, &problem)) {
    out.status = LocalHessianStatus::kSolverFailure;
    return out;
  }
  for (int k = 0; k < problem.num_views(); ++k) out.local_poses[k] = problem.poses[k].ToPose();
  const LocalIntrinsics& in = problem.intrinsics;
  out.intrinsic_camera_ids = in.camera_ids;
  out.intrinsic_free = in.free;
  out.intrinsics0.resize(in.num_unknowns);
  for (size_t c = 0; c < in.cameras.size(); ++c)
    out.intrinsics0.segment(in.offset[c], in.free[c].size()) = GatherIntrinsics(in.cameras[c], in.free[c]);
  out.track_points.assign(motion.track_ids.size(), PointStart());
  for (size_t i = 0; i < problem.points.size(); ++i) out.track_points[problem.point_track[i]].X = problem.points[i];
  for (const LocalObservation& o : problem.observations) ++out.track_points[problem.point_track[o.point]].support;
  out.rms_px = RmsReprojectionPx(problem);
  out.robust_cost = RobustCost(problem);
  out.depth_scale = MedianDepth(problem);

  const ReducedCameraSystem reduced = ReducedCameraMatrix(problem);  // paper eq. 3
  out.reduced_gradient = reduced.g;
  if (!reduced.h.allFinite() || !(out.depth_scale > 0) || !std::isfinite(out.depth_scale)) {
    out.status = LocalHessianStatus::kNonFinite;
    return out;
  }
  GaugePrior prior = ComputeGaugePrior(reduced.h, problem.poses, out.depth_scale, options);
  out.eigenvalue_ratio = prior.eigenvalue_ratio;
  if (options.prior_placement == PriorPlacement::kLocalBAAndHessian) {  // the one it used
    prior.P.topLeftCorner(problem.prior.rows(), problem.prior.cols()) = problem.prior;
    prior.F = Eigen::MatrixXd::Zero(prior.P.rows(), input_prior.F.cols());
    prior.F.topRows(problem.prior.rows()) = input_prior.F.topRows(problem.prior.rows());
  }
  out.prior_factor = std::move(prior.F);
  out.prior_mu = prior.mu;
  // min_eigenvalue_ratio <= 0 disables the rank test (whole-track motions: a direction of h
  // that no track of the motion sees is seen by the other motions).
  const bool rank_ok = !(options.min_eigenvalue_ratio > 0) || prior.eigenvalue_ratio >= options.min_eigenvalue_ratio;
  if (!rank_ok || !(prior.mu > 0)) {
    out.status = LocalHessianStatus::kIllConditioned;
    return out;
  }
  const Eigen::MatrixXd h = reduced.h + prior.P;
  out.h = SymmetricMatrix(h);
  // Minimiser of the quadratic of paper eq. 3, delta^T h delta / 2 + g^T delta (Ceres'
  // 1/2 |r|^2 convention): -h^-1 g. g is orthogonal to the similarity directions (the cost
  // is invariant under them), so the prior on those directions does not bias the step. As a
  // pseudo-inverse: a whole-track motion may leave a view's direction unseen (a view few of
  // its tracks reach; the other motions see it), and that direction then takes no step
  // rather than an unbounded one (LDLT: a zero pivot gives a zero component).
  // The factor itself is not kept (LocalHessian::Factor recomputes it), only checked.
  out.factor = options.factor;
  Eigen::MatrixXd V;
  Eigen::VectorXd D;
  if (options.factor == HessianFactor::kLdlt) {
    out.newton_step = -FactorReducedMatrixLdlt(h, &V, &D).solve(out.reduced_gradient);
  } else {
    DecomposeReducedMatrix(h, &V, &D);  // paper eq. 5
    out.newton_step = -PseudoInverseSolve(V, D, out.reduced_gradient);
  }
  if (!V.allFinite() || !D.allFinite() || !(D.size() > 0 && D.maxCoeff() > 0) || !out.newton_step.allFinite()) {
    out.status = LocalHessianStatus::kNonFinite;
    return out;
  }
  out.status = LocalHessianStatus::kOk;
  return out;
}

void LocalHessian::Factor(Eigen::MatrixXd* V, Eigen::VectorXd* D) const {
  if (factor == HessianFactor::kLdlt) {
    FactorReducedMatrixLdlt(h.Dense(), V, D);
  } else {
    DecomposeReducedMatrix(h.Dense(), V, D);
  }
}

ObservationShares CountObservationShares(const Reconstruction& tracks, const std::vector<LocalMotion>& motions) {
  ObservationShares shares;
  for (const LocalMotion& t : motions)
    for (const uint64_t tid : t.track_ids) {
      const auto pit = tracks.points3D.find(tid);
      if (pit == tracks.points3D.end()) continue;
      for (const uint32_t image_id : t.image_ids)
        for (const TrackElement& el : pit->second.track)
          if (el.image_id == image_id) {
            ++shares[{el.image_id, tid}];
            break;  // an image seeing the track twice: its first observation (BuildLocalBundleProblem)
          }
    }
  return shares;
}

LocalHessianOptions PaperTripletLocalHessianOptions() {
  LocalHessianOptions o;
  o.solver.max_iterations = 1;
  o.attenuation_q = 10.0;
  o.min_eigenvalue_ratio = 1e-10;
  o.factor = HessianFactor::kEigen;
  return o;
}

LocalHessianResult ComputeLocalHessians(const Reconstruction& tracks, const std::vector<LocalMotion>& motions,
                                        const LocalHessianOptions& options, const ObservationShares* given,
                                        const FreeIntrinsics* free) {
  LocalHessianResult result;
  result.hessians.resize(motions.size());
  std::unique_ptr<tbb::global_control> limit;
  if (options.num_threads > 0)
    limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, options.num_threads);
  ObservationShares counted;
  if (options.shared_observation_weighting && !given) counted = CountObservationShares(tracks, motions);
  const ObservationShares* sp = !options.shared_observation_weighting ? nullptr : given ? given : &counted;
  // Each motion writes only its own slot: the result does not depend on scheduling.
  tbb::parallel_for(size_t(0), motions.size(), [&](size_t i) {
    result.hessians[i] = ComputeLocalHessian(tracks, motions[i], static_cast<int>(i), options, sp, free);
  });
  for (const LocalHessian& h : result.hessians) ++result.status_counts[static_cast<int>(h.status)];
  std::string rejected;
  for (int s = 1; s < kNumLocalHessianStatus; ++s)
    if (result.status_counts[s] > 0)
      rejected += std::string(" ") + LocalHessianStatusName(static_cast<LocalHessianStatus>(s)) + "=" +
                  std::to_string(result.status_counts[s]);
  PGBA_LOG_DEBUG << "local hessians: " << result.num_ok() << " of " << motions.size() << " motions ok"
                << (rejected.empty() ? "" : "; rejected:" + rejected);
  return result;
}

}  // namespace pgba
