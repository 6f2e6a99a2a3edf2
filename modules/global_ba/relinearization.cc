// Re-linearisation of the local models at the pointless solution (RelinearizedGlobalBA,
// global_ba.h): the local Hessians re-taken where the solution puts each motion, then the
// global BA solved again on them. With whole-track motions this is Gauss-Newton on the
// point-based BA with the points eliminated (whole_track_motions.h): each pass costs one
// pass over the observations (re-triangulation, Schur complement) plus one global solve.
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numeric>
#include <utility>
#include <vector>

#include "modules/global_ba/global_ba.h"
#include "modules/global_ba/global_ba_solve.h"
#include "modules/global_ba/motion_residual.h"
#include "modules/global_ba/motion_similarity.h"
#include "modules/global_ba/motion_weighting.h"
#include "modules/global_ba/relinearized_models.h"
#include "pgba/geometry/triangulation.h"
#include "pgba/optim/intrinsics.h"
#include "pgba/optim/pose_parameterization.h"
#include "pgba/util/error.h"
#include "pgba/util/logging.h"
#include "pgba/util/text_format.h"
#include "pgba/util/timer.h"
#include "pgba/util/upper_median.h"

namespace pgba {

namespace {

using internal::FreeIntrinsicsOf;
using internal::IntrinsicSizes;
using internal::Models;
using internal::NoiseVariance;
using internal::RunGlobalBA;
using internal::SharesOf;
using internal::TotalRobustCost;

// How far `result` moved each motion from its linearisation point (the local poses of
// `hessians[i]`), in noise sigmas: |W_s (x_s - x_lin_s)| / (unit_s sigma_s), NaN for a motion
// `result` did not use or without a noise estimate.
std::vector<double> Displacements(const GlobalBAResult& result, const std::vector<LocalHessian>& hessians,
                                  const GlobalBAOptions& options) {
  std::vector<double> d(hessians.size(), std::numeric_limits<double>::quiet_NaN());
  for (size_t i = 0; i < hessians.size(); ++i) {
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
    d[i] = std::sqrt(f.SquaredNorm(x, sim.x.data(), k)) / (ResidualUnit(h, options) * std::sqrt(v));
  }
  return d;
}

// The displacements of the motions `relinearized` (the others and NaN left out): their largest
// value with `largest`, else their median; 0 when none.
double Displacement(const std::vector<double>& displacements, const std::vector<int>& relinearized, bool largest) {
  std::vector<double> d;
  for (const int i : relinearized)
    if (std::isfinite(displacements[i])) d.push_back(displacements[i]);
  if (d.empty()) return 0.0;
  return largest ? *std::max_element(d.begin(), d.end()) : UpperMedian(d);
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
// solution, and restarting at initial_trust_region_radius damps the weak directions again
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
      PGBA_LOG_DEBUG << "global BA: " << e.what() << " from the carried trust region radius "
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

// The relative change of the true robust cost from `before` to `after` (positive: lower).
double RelativeDecrease(double before, double after) { return (before - after) / before; }

// GlobalBAOptions::relinearize_checked: Gauss-Newton over re-linearisation passes, each step
// kept only if the true robust cost falls, until the stopping rule of global_ba.h says
// converged (or the safety cap ends it).
GlobalBAResult CheckedRelinearization(const Reconstruction& tracks, const LocalHessianOptions& lh_options,
                                      const std::map<uint32_t, Pose>& initial_poses,
                                      const std::vector<LocalMotion>& motions, std::vector<LocalHessian> hessians,
                                      const GlobalBAOptions& options,
                                      const GlobalBAIterationCallback& callback, const GcpInput* gcps,
                                      const std::function<bool(const std::map<uint32_t, Pose>&)>& near_enough = nullptr) {
  Timer timer;
  GlobalBAOptions pointless = options;
  pointless.weighting = TripletWeighting::kHessian;
  LocalHessianOptions at_solution = lh_options;
  at_solution.solver.max_iterations = 0;
  const ObservationShares shares = SharesOf(tracks, motions, at_solution);
  // Every solve is checked by the pass after it, at the looser tolerance.
  GlobalBAOptions checked = pointless;
  if (options.max_relinearizations > 0) {
    checked.solver.function_tolerance =
        std::max(options.solver.function_tolerance, options.relinearized_function_tolerance);
    checked.solver.stop_at_refused_step = true;
  }

  Models models(motions, std::move(hessians));
  GlobalBAResult trial = RunGlobalBA(initial_poses, motions, models.hessians(), checked, callback, gcps);
  GlobalBASummary total = trial.summary;
  // The kept state: the initial poses (cost of the models taken there), then each kept step.
  GlobalBAResult kept = trial;
  for (auto& [id, pose] : kept.poses) pose = initial_poses.at(id);
  for (auto& [id, k] : kept.intrinsics) {
    k.values = k.initial;
    k.stddev.setConstant(std::numeric_limits<double>::quiet_NaN());
  }
  const std::map<uint32_t, GlobalIntrinsics> first = trial.intrinsics;
  double cost = TotalRobustCost(models.hessians(), trial);
  total.passes.push_back({cost, true, std::numeric_limits<double>::quiet_NaN(), lh_options.max_reprojection_px});
  if (options.max_relinearizations == 0) {
    kept = trial;
    total.stop_reason = "no_relinearization";
    total.converged = false;
  }
  while (options.max_relinearizations > 0) {
    // How far the step moved the motions from the models it was taken on, measured before
    // those are replaced by the models re-taken there.
    const std::vector<double> moved = Displacements(trial, models.hessians(), pointless);
    if (total.relinearizations > 0) {
      // A step that moved every motion by less than relinearize_tolerance noise sigmas stays
      // where the models it was solved on are exact to second order: re-taking them there
      // (one more pass over the observations) would only confirm it. The first step is always
      // checked: it starts from poses no model was taken at a solution of.
      std::vector<int> every(moved.size());
      std::iota(every.begin(), every.end(), 0);
      const double step = Displacement(moved, every, /*largest=*/true);
      if (step < options.relinearize_tolerance) {
        kept = trial;
        total.passes.push_back({std::numeric_limits<double>::quiet_NaN(), true, step, lh_options.max_reprojection_px});
        total.relinearization_displacement = step;
        total.stop_reason = "step_tolerance";
        PGBA_LOG_DEBUG << "global BA pass " << total.passes.size() - 1 << ": motions moved up to " << step
                       << " noise sigmas, below relinearize_tolerance: kept without re-taking the models";
        break;
      }
    }
    Timer pass;
    const std::vector<int> retaken = models.RetakeAt(tracks, at_solution, &shares, motions, trial);
    total.relinearization_seconds += pass.Seconds();
    const double trial_cost = TotalRobustCost(models.hessians(), trial);
    // An unknown starting cost (local Hessians read from an older workspace file): the first
    // step is taken unchecked.
    const bool unknown = !std::isfinite(cost);
    const double decrease = unknown ? 1.0 : RelativeDecrease(cost, trial_cost);
    const bool refused = !unknown && !(trial_cost < cost);
    const double displacement = Displacement(moved, retaken, /*largest=*/true);
    total.passes.push_back({trial_cost, !refused, displacement, lh_options.max_reprojection_px});
    PGBA_LOG_DEBUG << "global BA pass " << total.passes.size() - 1 << ": robust reprojection cost " << cost
                     << " -> " << trial_cost << ", motions moved up to " << displacement << " noise sigmas"
                     << (refused ? " (step refused: the last kept poses stay)" : "");
    if (refused) {
      total.stop_reason = "refused_step";
      total.converged = -decrease <= options.relinearize_cost_tolerance;
      break;
    }
    cost = trial_cost;
    kept = trial;
    total.relinearizations += 1;
    total.relinearization_displacement = displacement;
    if (near_enough && near_enough(kept.poses)) {
      total.stop_reason = "near_enough";
      break;
    }
    if (decrease < options.relinearize_cost_tolerance) {
      total.stop_reason = "cost_tolerance";
      break;
    }
    if (displacement < options.relinearize_tolerance) {
      total.stop_reason = "step_tolerance";
      break;
    }
    if (total.relinearizations == options.max_relinearizations) {
      total.stop_reason = "max_relinearizations";
      total.converged = false;
      break;
    }
    trial = SolveAgain(kept.poses, models, checked, callback, gcps, &total);
  }
  // A first step refused within the cost tolerance leaves poses already at the minimum (one
  // motion over every image is the point-based BA itself); beyond it the start stays unadjusted.
  if (total.relinearizations == 0 && total.stop_reason == "refused_step" && total.converged)
    PGBA_LOG_DEBUG << "global BA: the initial poses are its minimum already (the first step changed the cost by "
                   << FormatNumber("%+.2g", 100.0 * (total.passes.back().robust_cost - cost) / cost) << "%)";
  else if (total.relinearizations == 0 && total.stop_reason == "refused_step")  // the mapper says what follows
    PGBA_LOG_DEBUG << "global BA: its first step raised the reprojection error (robust cost +"
                  << FormatNumber("%.0f", 100.0 * (total.passes.back().robust_cost - cost) / cost) << "%): the "
                  << kept.poses.size() << " images keep the poses it started from; the verification after the "
                  << "adjustment checks them against their observations";
  total.final_cost = kept.summary.final_cost;
  total.robust_scale = kept.summary.robust_scale;
  total.num_motions_downweighted = kept.summary.num_motions_downweighted;
  total.misfit_ratio = kept.summary.misfit_ratio;
  total.seconds = timer.Seconds();
  kept.summary = total;
  for (auto& [id, k] : kept.intrinsics) k.initial = first.at(id).initial;  // before every pass
  return kept;
}

// The paper's unchecked re-linearisation (relinearize_checked false): PointlessGlobalBA, then,
// if the misfit trigger fires, passes until the median displacement is below the tolerance.
GlobalBAResult UncheckedRelinearization(const Reconstruction& tracks, const LocalHessianOptions& lh_options,
                                        const std::map<uint32_t, Pose>& initial_poses,
                                        const std::vector<LocalMotion>& motions, std::vector<LocalHessian> hessians,
                                        const GlobalBAOptions& options,
                                        const GlobalBAIterationCallback& callback, const GcpInput* gcps) {
  Timer timer;
  GlobalBAOptions pointless = options;
  pointless.weighting = TripletWeighting::kHessian;
  GlobalBAResult result = RunGlobalBA(initial_poses, motions, hessians, pointless, callback, gcps);
  GlobalBASummary total = result.summary;
  const bool trigger = options.relinearize_misfit <= 0 || total.misfit_ratio > options.relinearize_misfit;
  const std::map<uint32_t, GlobalIntrinsics> first = result.intrinsics;
  total.stop_reason = options.max_relinearizations == 0 ? "no_relinearization" : "misfit_below_threshold";
  total.converged = options.max_relinearizations > 0;
  if (options.max_relinearizations > 0 && trigger) {
    PGBA_LOG_DEBUG << "global BA: misfit " << total.misfit_ratio
                     << " (local models disagree with their consensus): re-linearising the local hessians at the "
                        "solution";
    LocalHessianOptions at_solution = lh_options;
    at_solution.solver.max_iterations = 0;  // h and g where the solution puts the motion, points re-triangulated
    const ObservationShares shares = SharesOf(tracks, motions, at_solution);
    // The frames carry the local frame of each re-linearised model (its similarity from the
    // solution), for SimilarityInit::kFromTriplet.
    Models models(motions, std::move(hessians));
    total.stop_reason = "max_relinearizations";
    total.converged = false;
    for (int k = 1; k <= options.max_relinearizations; ++k) {
      Timer pass;
      const std::vector<int> relinearized = models.RetakeAt(tracks, at_solution, &shares, motions, result);
      total.relinearization_seconds += pass.Seconds();
      result = SolveAgain(result.poses, models, pointless, callback, gcps, &total);
      const GlobalBASummary& s = result.summary;
      total.final_cost = s.final_cost;
      total.robust_scale = s.robust_scale;
      total.num_motions_downweighted = s.num_motions_downweighted;
      total.misfit_ratio = s.misfit_ratio;
      total.relinearizations = k;
      total.relinearization_displacement =
          Displacement(Displacements(result, models.hessians(), pointless), relinearized, /*largest=*/false);
      PGBA_LOG_DEBUG << "global BA re-linearisation " << k << ": " << relinearized.size()
                       << " local hessians at the solution, moved " << total.relinearization_displacement
                       << " noise sigmas from them, misfit " << total.misfit_ratio;
      if (total.relinearization_displacement < options.relinearize_tolerance) {
        total.stop_reason = "step_tolerance";
        total.converged = true;
        break;
      }
    }
  }
  total.seconds = timer.Seconds();
  result.summary = total;
  for (auto& [id, k] : result.intrinsics) k.initial = first.at(id).initial;  // before every pass
  return result;
}

// The median reprojection error of the motions' tracks at `poses` (each track triangulated
// from its views there, a sample of at most kMaxTracks tracks spread over the motions),
// with the cameras of `tracks` updated by the models' intrinsics at their linearisation point.
double StartMedianResidual(const Reconstruction& tracks, const std::map<uint32_t, Pose>& poses,
                           const std::vector<LocalMotion>& motions) {
  // A sample of at most this many tracks (several thousand observations) puts the median
  // within about 2% (its standard error); the threshold it sets needs no more.
  constexpr size_t kMaxTracks = 2000;
  std::vector<uint64_t> ids;
  for (const LocalMotion& m : motions) ids.insert(ids.end(), m.track_ids.begin(), m.track_ids.end());
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  const size_t stride = std::max<size_t>(1, (ids.size() + kMaxTracks - 1) / kMaxTracks);
  TriangulationOptions wide;
  wide.outlier_px = 1e3;
  std::vector<double> residuals;
  for (size_t k = 0; k < ids.size(); k += stride) {
    const auto point = tracks.points3D.find(ids[k]);
    if (point == tracks.points3D.end()) continue;
    std::vector<TrackView> views;
    for (const TrackElement& el : point->second.track) {
      const auto pose = poses.find(el.image_id);
      if (pose == poses.end()) continue;
      const Image& image = tracks.images.at(el.image_id);
      views.push_back({pose->second, &tracks.cameras.at(image.camera_id), image.points2D[el.point2D_idx].xy});
    }
    if (views.size() < 2) continue;
    const TriangulatedPoint X = TriangulateTrack(views, wide);
    if (X.ok) residuals.insert(residuals.end(), X.residuals_px.begin(), X.residuals_px.end());
  }
  return residuals.empty() ? 0.0 : UpperMedian(residuals);
}

// GlobalBAOptions::start_outlier_factor: the checked passes first on models with a wider
// outlier threshold, then on models with the configured one re-taken where those ended.
GlobalBAResult GraduatedRelinearization(const Reconstruction& tracks, const LocalHessianOptions& lh_options,
                                        const std::map<uint32_t, Pose>& initial_poses,
                                        const std::vector<LocalMotion>& motions, std::vector<LocalHessian> hessians,
                                        const GlobalBAOptions& options,
                                        const GlobalBAIterationCallback& callback, const GcpInput* gcps) {
  if (options.start_outlier_factor <= 0 || options.max_relinearizations == 0)
    return CheckedRelinearization(tracks, lh_options, initial_poses, motions, std::move(hessians), options, callback,
                                  gcps);
  Timer timer;
  const double median = StartMedianResidual(tracks, initial_poses, motions);
  const double wide_px = options.start_outlier_factor * median;
  if (!(wide_px > lh_options.max_reprojection_px)) {
    GlobalBAResult r = CheckedRelinearization(tracks, lh_options, initial_poses, motions, std::move(hessians), options,
                                              callback, gcps);
    r.summary.start_median_px = median;
    return r;
  }
  PGBA_LOG_DEBUG << "global BA: the start is far from the solution (median reprojection error " << median
                << " px): first adjusted with observations up to " << wide_px << " px, then up to "
                << lh_options.max_reprojection_px << " px";
  const FreeIntrinsics free = FreeIntrinsicsOf(hessians);
  LocalHessianOptions wide = lh_options;
  wide.max_reprojection_px = wide_px;
  wide.solver.max_iterations = 0;
  const ObservationShares shares = SharesOf(tracks, motions, wide);
  // The wide models' points start from the given models' (the same frames): a warm
  // re-triangulation instead of one from scratch.
  LocalHessianResult first;
  {
    std::vector<LocalMotion> warm = motions;
    for (size_t i = 0; i < warm.size() && i < hessians.size(); ++i)
      if (hessians[i].track_points.size() == warm[i].track_ids.size()) warm[i].track_points = hessians[i].track_points;
    first = ComputeLocalHessians(tracks, warm, wide, &shares, free.empty() ? nullptr : &free);
  }
  const double first_seconds = timer.Seconds();
  // The wide phase ends as soon as the start is no longer far by the test that began it: the
  // configured threshold then keeps the inliers, and its own passes converge from there.
  const auto near_enough = [&](const std::map<uint32_t, Pose>& poses) {
    return !(options.start_outlier_factor * StartMedianResidual(tracks, poses, motions) > lh_options.max_reprojection_px);
  };
  const GlobalBAResult r = CheckedRelinearization(tracks, wide, initial_poses, motions, first.hessians, options,
                                                  callback, gcps, near_enough);
  // The configured models where the wide passes ended (the others as given).
  Timer retake;
  LocalHessianOptions at_solution = lh_options;
  at_solution.solver.max_iterations = 0;
  Models models(motions, std::move(hessians));
  {
    const Models wide_models(motions, first.hessians);
    models.RetakeAt(tracks, at_solution, &shares, motions, r, &wide_models);
  }
  first.hessians = std::vector<LocalHessian>();  // the wide models are done with
  const double retake_seconds = retake.Seconds();
  GlobalBAResult out = CheckedRelinearization(tracks, lh_options, r.poses, models.frames(), models.TakeHessians(), options,
                                              Shifted(callback, r.summary.iterations), gcps);
  GlobalBASummary& s = out.summary;
  s.iterations += r.summary.iterations;
  s.rounds += r.summary.rounds;
  s.relinearizations += r.summary.relinearizations + 1;
  s.relinearization_seconds += r.summary.relinearization_seconds + first_seconds + retake_seconds;
  s.cost_per_iteration.insert(s.cost_per_iteration.begin(), r.summary.cost_per_iteration.begin(),
                              r.summary.cost_per_iteration.end());
  s.passes.insert(s.passes.begin(), r.summary.passes.begin(), r.summary.passes.end());
  s.initial_cost = r.summary.initial_cost;
  s.converged = s.converged && r.summary.converged;
  if (!r.summary.converged) s.stop_reason = "wide_threshold_" + r.summary.stop_reason;
  s.start_median_px = median;
  s.start_outlier_px = wide_px;
  s.seconds = timer.Seconds();
  for (auto& [id, k] : out.intrinsics) k.initial = r.intrinsics.at(id).initial;  // before every pass
  return out;
}

}  // namespace

GlobalBAResult RelinearizedGlobalBA(const Reconstruction& tracks, const LocalHessianOptions& lh_options,
                                    const std::map<uint32_t, Pose>& initial_poses,
                                    const std::vector<LocalMotion>& motions, std::vector<LocalHessian> hessians,
                                    const GlobalBAOptions& options, const GlobalBAIterationCallback& callback,
                                    const GcpInput* gcps) {
  GlobalBAResult r =
      options.relinearize_checked
          ? GraduatedRelinearization(tracks, lh_options, initial_poses, motions, std::move(hessians), options, callback,
                                     gcps)
          : UncheckedRelinearization(tracks, lh_options, initial_poses, motions, std::move(hessians), options, callback,
                                     gcps);
  if (r.summary.stop_reason == "max_relinearizations")
    PGBA_LOG_WARN << "global BA: not converged after " << r.summary.relinearizations
                  << " re-linearisations (global_ba.max_relinearizations); the poses are the last pass's";
  return r;
}

}  // namespace pgba
