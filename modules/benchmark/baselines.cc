#include "benchmark/baselines.h"

#include <limits>
#include <stdexcept>

#include "benchmark/triplet_split_tracks.h"
#include "pgba/scene/triangulate_model.h"
#include "pgba/util/error.h"
#include "pgba/util/timer.h"

namespace pgba {

const char* RefinementMethodName(RefinementMethod method) {
  switch (method) {
    case RefinementMethod::kPointless:
      return "pointless";
    case RefinementMethod::kPointBased:
      return "pointbased";
    case RefinementMethod::kAveraging:
      return "averaging";
    case RefinementMethod::kPointBasedSplit:
      return "pointbased_split";
  }
  return "unknown";
}

namespace {

std::map<uint32_t, Pose> PosesOf(const Reconstruction& rec) {
  std::map<uint32_t, Pose> poses;
  for (const auto& [id, im] : rec.images) poses[id] = im.pose;
  return poses;
}

RefinementResult RefinePointBased(const Reconstruction& tracks, const std::map<uint32_t, Pose>& initial,
                                  const PointBasedOptions& options, const FreeIntrinsics& free, bool record_history) {
  RefinementResult r;
  ResetPeakRss();
  Timer prepare;
  Reconstruction model = TriangulateModel(tracks, initial);
  r.prepare_seconds = prepare.Seconds();
  if (model.points3D.empty()) throw InputError("point-based BA: no track could be triangulated");

  BundleAdjustmentProblem problem;
  ChooseGauge(model, &problem);
  problem.free_intrinsics = free;
  if (record_history) {
    r.history.push_back(PosesOf(model));
    problem.callback = [&r](const BundleAdjustmentIteration& it) {
      if (it.iteration > 0) r.history.push_back(PosesOf(*it.state));
    };
  }
  r.num_params = 6 * static_cast<int>(model.images.size()) + 3 * static_cast<int>(model.points3D.size());
  for (const auto& [id, f] : free) r.num_params += static_cast<int>(f.size());
  const bool two_passes = options.filter_max_error_px > 0;
  BundleAdjusterOptions first_pass = options.bundle;
  if (two_passes && !options.first_pass_loss.empty()) first_pass.loss.type = ParseLossType(options.first_pass_loss);
  Timer adjust;
  const BundleAdjustmentSummary first = BundleAdjust(problem, first_pass, &model);
  if (!first.usable) throw InputError("point-based BA: solver failure: " + first.message);
  r.iterations = first.iterations;
  size_t filtered = 0;
  if (two_passes) {
    filtered = FilterObservations(options.filter_max_error_px, &model);
    // The final pass always runs: it is the configured loss on the kept observations.
    const BundleAdjustmentSummary second = BundleAdjust(problem, options.bundle, &model);
    if (!second.usable) throw InputError("point-based BA: solver failure: " + second.message);
    r.iterations += second.iterations;
  }
  r.adjust_seconds = adjust.Seconds();
  r.peak_rss_mb = PeakRssMb();
  r.poses = PosesOf(model);
  if (!free.empty()) {
    r.cameras = model.cameras;
    for (const auto& [id, f] : free) {
      const Eigen::VectorXd nan = Eigen::VectorXd::Constant(f.size(), std::numeric_limits<double>::quiet_NaN());
      r.intrinsics.push_back(IntrinsicsRecord(id, model.cameras.at(id), f, GatherIntrinsics(tracks.cameras.at(id), f),
                                              GatherIntrinsics(model.cameras.at(id), f), nan));
    }
  }
  r.details = {{"points", model.points3D.size()},
               {"observations", first.num_observations},
               {"observations_filtered", filtered},
               {"linear_solver", first.linear_solver},
               {"converged", first.converged}};
  return r;
}

}  // namespace

RefinementResult RefinePoses(RefinementMethod method, const Reconstruction& tracks,
                             const std::map<uint32_t, Pose>& initial, const std::vector<LocalMotion>& triplets,
                             const PreparedHessians* hessians, const RefinementOptions& options,
                             bool record_history) {
  if (method == RefinementMethod::kPointless || method == RefinementMethod::kAveraging) {
    if (!hessians) throw std::invalid_argument("RefinePoses: local hessians are required for this method");
    if (method == RefinementMethod::kPointless) return RefinePointless(tracks, initial, *hessians, options, record_history);
    // Aver_BA: the same motions and solver as the pointless BA, scalar weights (global_ba.h).
    return RefineOnMotions("averaging", tracks, initial, *hessians, options, record_history,
                           [&](const std::map<uint32_t, Pose>& start, const GlobalBAIterationCallback& callback) {
                             return AveragingGlobalBA(start, hessians->motions, hessians->result.hessians,
                                                      options.global_ba, callback);
                           });
  }
  RefinementResult r;
  if (method == RefinementMethod::kPointBased) {
    r = RefinePointBased(tracks, initial, options.point_based, SelectRefinedIntrinsics(tracks, options), record_history);
  } else {
    Timer split;
    // Over the motions the local hessians model (the triplets unless local_motions.views > 3).
    const Reconstruction split_tracks =
        hessians ? SplitTracksByMotions(tracks, hessians->motions) : SplitTracksByTriplets(tracks, triplets);
    const double split_seconds = split.Seconds();
    r = RefinePointBased(split_tracks, initial, options.point_based, SelectRefinedIntrinsics(tracks, options),
                         record_history);
    r.prepare_seconds += split_seconds;
  }
  CheckRefinedCameras(r);
  LogRefinement(RefinementMethodName(method), r);
  return r;
}

}  // namespace pgba
