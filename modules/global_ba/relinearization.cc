// Re-linearisation of the local models at the pointless solution (RelinearizedGlobalBA,
// global_ba.h): the local Hessians re-taken where the solution puts each motion, then the
// global BA solved again on them. With whole-track motions this is Gauss-Newton on the
// point-based BA with the points eliminated (whole_track_motions.h): each pass costs one
// pass over the observations (re-triangulation, Schur complement) plus one global solve.
#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include "modules/global_ba/global_ba.h"
#include "modules/global_ba/global_ba_solve.h"
#include "modules/global_ba/motion_residual.h"
#include "modules/global_ba/motion_similarity.h"
#include "modules/global_ba/motion_weighting.h"
#include "modules/global_ba/relinearized_models.h"
#include "pgba/optim/intrinsics.h"
#include "pgba/optim/pose_parameterization.h"
#include "pgba/util/error.h"
#include "pgba/util/logging.h"
#include "pgba/util/timer.h"
#include "pgba/util/upper_median.h"

namespace pgba {

namespace {

using internal::FreeIntrinsicsOf;
using internal::IntrinsicSizes;
using internal::Models;
using internal::NoiseVariance;
using internal::RelinearizeAt;
using internal::RunGlobalBA;
using internal::SharesOf;
using internal::TotalRobustCost;

// Median over the motions `relinearized` of |W_s (x_s - x_lin_s)| / (unit_s sigma_s): how far
// `result` moved from the linearisation points (the local poses of `hessians[i]`), in noise
// sigmas.
double Displacement(const GlobalBAResult& result, const std::vector<LocalHessian>& hessians,
                    const std::vector<int>& relinearized, const GlobalBAOptions& options) {
  std::vector<double> d;
  for (const int i : relinearized) {
    const LocalHessian& h = hessians[i];
    const double v = NoiseVariance(h);
    if (!std::isfinite(v) || !(result.irls_weights[i] > 0)) continue;
    std::vector<PoseBlock> blocks;
    std::vector<Pose> global;
    std::vector<Eigen::Matrix3d> R0;
    std::vector<const double*> x;
    for (const uint32_t id : h.image_ids) {
      global.push_back(result.poses.at(id));
      blocks.push_back(PoseBlock::FromPose(global.back()));
      R0.push_back(blocks.back().R0);
    }
    for (const PoseBlock& b : blocks) x.push_back(b.x.data());
    const MotionSimilarity sim = SimilarityFromSim3(global, result.similarities[i]);
    const MotionResidual f(R0, sim, h.local_poses, MotionWeightOf(h, options), Eigen::VectorXd(), h.intrinsics0,
                           IntrinsicSizes(h));
    std::vector<const double*> k;
    for (const uint32_t id : h.intrinsic_camera_ids) k.push_back(result.intrinsics.at(id).values.data());
    d.push_back(f.Evaluate(x, sim.x.data(), k).norm() / (ResidualUnit(h, options) * std::sqrt(v)));
  }
  return d.empty() ? 0.0 : UpperMedian(d);
}

// `callback` seeing iterations counted on after `offset` (one continuous count over solves).
GlobalBAIterationCallback Shifted(const GlobalBAIterationCallback& callback, int offset) {
  if (!callback) return nullptr;
  return [callback, offset](const GlobalBAIteration& it) {
    GlobalBAIteration c = it;
    c.iteration += offset;
    callback(c);
  };
}

// A re-linearised solve from `poses`, its iterations counted on after those in `total` (the
// callback sees one continuous count) and added to it. It starts from the trust region the
// previous solve ended with: the re-taken models differ little from the old ones near the
// solution, and restarting at initial_trust_region_radius damped the weak directions again
// (long-focal loop seed 1, the last solve: 12 iterations from 1e8, 4 from the carried 3.5e10).
// A carried radius can leave a weak direction undamped enough that the first pose system is
// not positive definite (self-calibrating planar:4, focal 1535 -> 1380 px in one pass, carried
// 1.1e12): the solve is then taken again from initial_trust_region_radius.
GlobalBAResult SolveAgain(const std::map<uint32_t, Pose>& poses, const Models& models, const GlobalBAOptions& given,
                          const GlobalBAIterationCallback& callback, const GcpInput* gcps, GlobalBASummary* total) {
  GlobalBAOptions options = given;
  options.solver.initial_trust_region_radius = std::max(given.solver.initial_trust_region_radius, total->final_trust_region_radius);
  const int offset = total->iterations;
  const GlobalBAIterationCallback shifted = Shifted(callback, offset);
  const auto solve = [&] {
    return RunGlobalBA(poses, models.frames(), models.hessians(), options, shifted, gcps, /*report_start=*/false);
  };
  GlobalBAResult result;
  if (options.solver.initial_trust_region_radius > given.solver.initial_trust_region_radius) {
    try {
      result = solve();
    } catch (const InputError& e) {
      PGBA_LOG_INFO << "global BA: " << e.what() << " from the carried trust region radius "
                    << options.solver.initial_trust_region_radius << "; solved again from "
                    << given.solver.initial_trust_region_radius;
      options.solver.initial_trust_region_radius = given.solver.initial_trust_region_radius;
      result = solve();
    }
  } else {
    result = solve();
  }
  const GlobalBASummary& s = result.summary;
  total->iterations += s.iterations;
  total->rounds += s.rounds;
  total->final_trust_region_radius = s.final_trust_region_radius;
  total->cost_per_iteration.insert(total->cost_per_iteration.end(), s.cost_per_iteration.begin(),
                                   s.cost_per_iteration.end());
  return result;
}

// One Levenberg-Marquardt step on `models` from `poses`: a single iteration of the solve with
// damping diag(J^T J) / radius (GlobalBAOptions::relinearize_damped_steps). The trust region
// carried for the undamped solves is left as it was.
GlobalBAResult SolveDamped(const std::map<uint32_t, Pose>& poses, const Models& models, const GlobalBAOptions& given,
                           double radius, const GlobalBAIterationCallback& callback, const GcpInput* gcps,
                           GlobalBASummary* total) {
  GlobalBAOptions options = given;
  options.max_rounds = 1;
  options.solver.max_iterations = 1;
  options.solver.initial_trust_region_radius = radius;
  const double carried = total->final_trust_region_radius;
  total->final_trust_region_radius = 0.0;
  GlobalBAResult result = SolveAgain(poses, models, options, callback, gcps, total);
  total->final_trust_region_radius = carried;
  return result;
}

// GlobalBAOptions::relinearize_checked: Gauss-Newton over re-linearisation passes, each step
// kept only if the true robust cost falls. A refused step is taken again, damped, from the
// same linearisation (Levenberg-Marquardt across the passes, relinearize_damped_steps).
GlobalBAResult CheckedRelinearization(const Reconstruction& tracks, const LocalHessianOptions& lh_options,
                                      const std::map<uint32_t, Pose>& initial_poses,
                                      const std::vector<LocalMotion>& motions,
                                      const std::vector<LocalHessian>& hessians, const GlobalBAOptions& options,
                                      const GlobalBAIterationCallback& callback, const GcpInput* gcps) {
  Timer timer;
  GlobalBAOptions pointless = options;
  pointless.weighting = TripletWeighting::kHessian;
  LocalHessianOptions at_solution = lh_options;
  at_solution.solver.max_iterations = 0;
  const ObservationShares shares = SharesOf(tracks, motions, at_solution);

  // A solve whose solution is re-linearised next stops at the looser tolerance.
  GlobalBAOptions before_pass = pointless;
  before_pass.solver.function_tolerance =
      std::max(options.solver.function_tolerance, options.relinearized_function_tolerance);
  before_pass.solver.stop_at_refused_step = true;
  const auto solve_options = [&](int passes_left) -> const GlobalBAOptions& {
    return passes_left > 0 ? before_pass : pointless;
  };
  // Levenberg-Marquardt across the passes: 0 while the steps are Gauss-Newton's (the solve
  // converged on the models), else the damped step's trust-region radius (diag(J^T J) /
  // radius), updated by the gain ratio of the true robust cost as Ceres updates its own.
  double radius = 0.0, nu = 2.0;
  int refusals_left = options.relinearize_damped_steps;
  const int max_kept = options.max_relinearizations;

  Models models(motions, hessians);
  GlobalBAResult trial = RunGlobalBA(initial_poses, motions, hessians, solve_options(max_kept), callback, gcps);
  GlobalBASummary total = trial.summary;
  // The kept state: the initial poses (cost of the models taken there), then each kept step.
  GlobalBAResult kept = trial;
  for (auto& [id, pose] : kept.poses) pose = initial_poses.at(id);
  for (auto& [id, k] : kept.intrinsics) {
    k.values = k.initial;
    k.stddev.setConstant(std::numeric_limits<double>::quiet_NaN());
  }
  const std::map<uint32_t, GlobalIntrinsics> first = trial.intrinsics;
  double cost = TotalRobustCost(models.hessians(), nullptr, trial);
  int kept_steps = 0;
  // The solve that produces the next trial from the kept state and its models.
  const auto next_trial = [&](int passes_left) {
    return radius > 0 ? SolveDamped(kept.poses, models, solve_options(passes_left), radius, callback, gcps, &total)
                      : SolveAgain(kept.poses, models, solve_options(passes_left), callback, gcps, &total);
  };
  while (kept_steps < max_kept) {
    Timer pass;
    Models::Retaken retaken = RelinearizeAt(tracks, at_solution, &shares, motions, models, trial);
    total.relinearization_seconds += pass.Seconds();
    const double trial_cost = TotalRobustCost(models.hessians(), &retaken, trial);
    const double predicted = 2.0 * (trial.summary.initial_cost - trial.summary.final_cost);
    // An unknown starting cost (local Hessians read from an older workspace file): the first
    // step is taken unchecked.
    const bool unknown = !std::isfinite(cost);
    const bool refused = !unknown && !(trial_cost < cost);
    PGBA_LOG_INFO << "global BA re-linearisation " << kept_steps + 1
                  << (radius > 0 ? " (damped, radius " + std::to_string(radius) + ")" : std::string())
                  << ": robust cost " << cost << " -> " << trial_cost << " (the models predicted " << predicted
                  << " lower)"
                  << (!refused ? " (step kept)"
                      : refusals_left > 0 ? " (step refused: damped again from the last kept step)"
                                          : " (step refused: stopping at the last kept step)");
    if (refused) {
      if (refusals_left == 0) break;
      --refusals_left;
      if (radius > 0) {
        radius /= nu;
        nu *= 2.0;
      } else {
        radius = options.relinearize_damping_radius;
      }
      trial = next_trial(max_kept - kept_steps);
      continue;
    }
    const double decrease = unknown ? 1.0 : (cost - trial_cost) / cost;
    // How far the step moved from the models it was solved with, in noise sigmas.
    total.relinearization_displacement = Displacement(trial, models.hessians(), retaken.index, pointless);
    models.Adopt(std::move(retaken));
    const double gain = predicted > 0 && !unknown ? (cost - trial_cost) / predicted : 1.0;
    cost = trial_cost;
    kept = trial;
    total.relinearizations = ++kept_steps;
    // A damped step that was kept: the radius grows with the gain ratio (Ceres' rule), back
    // to Gauss-Newton's undamped solve once the damping is negligible. A damped step's small
    // displacement says nothing of convergence.
    const bool damped = radius > 0;
    if (damped) {
      radius /= std::max(1.0 / 3.0, 1.0 - std::pow(2.0 * std::min(gain, 1.0) - 1.0, 3));
      nu = 2.0;
      if (radius >= options.solver.initial_trust_region_radius) radius = 0.0;
    }
    if (decrease < options.relinearize_cost_tolerance ||
        (!damped && total.relinearization_displacement < options.relinearize_tolerance))
      break;
    trial = next_trial(max_kept - kept_steps);
    // The last solve is taken as it is: its own check would cost one more pass, and it starts
    // from models that a kept step just produced (the same as the unchecked re-linearisation).
    if (kept_steps == max_kept) kept = trial;
  }
  if (total.relinearizations == 0)
    PGBA_LOG_WARN << "global BA: the re-linearised first step raised the robust reprojection cost; the initial poses "
                     "are kept";
  total.final_cost = kept.summary.final_cost;
  total.robust_scale = kept.summary.robust_scale;
  total.num_motions_downweighted = kept.summary.num_motions_downweighted;
  total.misfit_ratio = kept.summary.misfit_ratio;
  total.seconds = timer.Seconds();
  kept.summary = total;
  for (auto& [id, k] : kept.intrinsics) k.initial = first.at(id).initial;  // before every pass
  return kept;
}

// GlobalBAOptions::relinearize_robust_passes_self_calibrating: the checked passes first on
// Cauchy local Hessians (taken again at the motions' linearisation points), then on models
// with the configured loss re-taken where those passes ended.
GlobalBAResult RobustThenChecked(const Reconstruction& tracks, const LocalHessianOptions& lh_options,
                                 const std::map<uint32_t, Pose>& initial_poses, const std::vector<LocalMotion>& motions,
                                 const std::vector<LocalHessian>& hessians, const GlobalBAOptions& options,
                                 const GlobalBAIterationCallback& callback, const GcpInput* gcps) {
  Timer timer;
  LocalHessianOptions robust = lh_options;
  robust.loss.type = LossType::kCauchy;
  const FreeIntrinsics free = FreeIntrinsicsOf(hessians);
  const ObservationShares shares = SharesOf(tracks, motions, robust);
  const LocalHessianResult first = ComputeLocalHessians(tracks, motions, robust, &shares, &free);
  const double first_seconds = timer.Seconds();
  GlobalBAOptions robust_passes = options;
  robust_passes.max_relinearizations = options.relinearize_robust_passes_self_calibrating;
  const GlobalBAResult r =
      CheckedRelinearization(tracks, robust, initial_poses, motions, first.hessians, robust_passes, callback, gcps);
  PGBA_LOG_INFO << "global BA: " << r.summary.relinearizations << " redescending (Cauchy) passes, then the local "
                << "hessians with the " << LossTypeName(lh_options.loss.type) << " loss";
  // The configured models where the Cauchy passes ended (the others as given).
  Timer retake;
  LocalHessianOptions at_solution = lh_options;
  at_solution.solver.max_iterations = 0;
  Models models(motions, hessians);
  models.Adopt(RelinearizeAt(tracks, at_solution, &shares, motions, models, r));
  const double retake_seconds = retake.Seconds();
  const int offset = r.summary.iterations;
  const GlobalBAIterationCallback shifted = Shifted(callback, offset);
  GlobalBAResult out = CheckedRelinearization(tracks, lh_options, r.poses, models.frames(), models.hessians(), options,
                                              shifted, gcps);
  GlobalBASummary& s = out.summary;
  s.iterations += r.summary.iterations;
  s.rounds += r.summary.rounds;
  s.relinearizations += r.summary.relinearizations + 1;
  s.relinearization_seconds += r.summary.relinearization_seconds + first_seconds + retake_seconds;
  s.cost_per_iteration.insert(s.cost_per_iteration.begin(), r.summary.cost_per_iteration.begin(),
                              r.summary.cost_per_iteration.end());
  s.initial_cost = r.summary.initial_cost;
  s.seconds = timer.Seconds();
  for (auto& [id, k] : out.intrinsics) k.initial = r.intrinsics.at(id).initial;  // before every pass
  return out;
}

}  // namespace

GlobalBAResult RelinearizedGlobalBA(const Reconstruction& tracks, const LocalHessianOptions& lh_options,
                                    const std::map<uint32_t, Pose>& initial_poses,
                                    const std::vector<LocalMotion>& motions, const std::vector<LocalHessian>& hessians,
                                    const GlobalBAOptions& options, const GlobalBAIterationCallback& callback,
                                    const GcpInput* gcps) {
  if (options.relinearize_checked) {
    GlobalBAOptions passes = options;
    const bool self_calibrating =
        std::any_of(hessians.begin(), hessians.end(), [](const LocalHessian& h) { return h.num_intrinsics() > 0; });
    if (self_calibrating) passes.max_relinearizations = options.max_relinearizations_self_calibrating;
    if (self_calibrating && options.relinearize_robust_passes_self_calibrating > 0)
      return RobustThenChecked(tracks, lh_options, initial_poses, motions, hessians, passes, callback, gcps);
    return CheckedRelinearization(tracks, lh_options, initial_poses, motions, hessians, passes, callback, gcps);
  }
  Timer timer;
  GlobalBAOptions pointless = options;
  pointless.weighting = TripletWeighting::kHessian;
  GlobalBAResult result = RunGlobalBA(initial_poses, motions, hessians, pointless, callback, gcps);
  GlobalBASummary total = result.summary;
  const bool trigger = options.relinearize_misfit <= 0 || total.misfit_ratio > options.relinearize_misfit;
  const std::map<uint32_t, GlobalIntrinsics> first = result.intrinsics;
  if (options.max_relinearizations > 0 && trigger) {
    PGBA_LOG_INFO << "global BA: misfit " << total.misfit_ratio << " (local models disagree with their consensus): "
                  << "re-linearising the local hessians at the solution";
    LocalHessianOptions at_solution = lh_options;
    at_solution.solver.max_iterations = 0;  // h and g where the solution puts the motion, points re-triangulated
    const ObservationShares shares = SharesOf(tracks, motions, at_solution);
    // The frames carry the local frame of each re-linearised model (its similarity from the
    // solution), for SimilarityInit::kFromTriplet.
    Models models(motions, hessians);
    for (int k = 1; k <= options.max_relinearizations; ++k) {
      Timer pass;
      Models::Retaken retaken = RelinearizeAt(tracks, at_solution, &shares, motions, models, result);
      const std::vector<int> relinearized = retaken.index;
      models.Adopt(std::move(retaken));
      total.relinearization_seconds += pass.Seconds();
      result = SolveAgain(result.poses, models, pointless, callback, gcps, &total);
      const GlobalBASummary& s = result.summary;
      total.final_cost = s.final_cost;
      total.robust_scale = s.robust_scale;
      total.num_motions_downweighted = s.num_motions_downweighted;
      total.misfit_ratio = s.misfit_ratio;
      total.relinearizations = k;
      total.relinearization_displacement = Displacement(result, models.hessians(), relinearized, pointless);
      PGBA_LOG_INFO << "global BA re-linearisation " << k << ": " << relinearized.size()
                    << " local hessians at the solution, moved " << total.relinearization_displacement
                    << " noise sigmas from them, misfit " << total.misfit_ratio;
      if (total.relinearization_displacement < options.relinearize_tolerance) break;
    }
  }
  total.seconds = timer.Seconds();
  result.summary = total;
  for (auto& [id, k] : result.intrinsics) k.initial = first.at(id).initial;  // before every pass
  return result;
}

}  // namespace pgba
