#include "mapper/pose_refinement.h"

#include <cmath>
#include <limits>
#include <string>

#include "pgba/io/option_ranges.h"
#include "mapper/linearization_start.h"
#include "pgba/io/report.h"
#include "pgba/util/error.h"
#include "pgba/util/logging.h"
#include "pgba/util/timer.h"

namespace pgba {

void AddRefinementSections(ConfigSchema* schema) {
  const RefinementOptions defaults;
  schema->Add("local_motions", defaults.local_motions)
      .Add("local_hessian", defaults.local_hessian)
      .Add("global_ba", defaults.global_ba)
      .Add("point_based", defaults.point_based)
      .Add("intrinsics", defaults.intrinsics);
}

void ReadRefinementOptions(const Config& config, RefinementOptions* options) {
  ReadSection(config, "local_motions", &options->local_motions);
  ReadSection(config, "local_hessian", &options->local_hessian);
  ReadSection(config, "global_ba", &options->global_ba);
  ReadSection(config, "point_based", &options->point_based);
  ReadSection(config, "intrinsics", &options->intrinsics);
}

FreeIntrinsics SelectRefinedIntrinsics(const Reconstruction& tracks, const RefinementOptions& options) {
  if (RefinesIntrinsics(options.intrinsics, options.calibration_is_prior))
    return SelectFreeIntrinsics(tracks.cameras, options.intrinsics);
  if (options.intrinsics.cameras != IntrinsicsCameras::kAuto) return {};
  // Tracks from a file: "auto" still refines the cameras whose focal is COLMAP's
  // 1.2 max(w, h) guess (Camera::has_prior_focal_length false, kept through cameras.txt).
  std::map<uint32_t, Camera> guessed;
  for (const auto& [id, camera] : tracks.cameras)
    if (!camera.has_prior_focal_length) guessed[id] = camera;
  return SelectFreeIntrinsics(guessed, options.intrinsics);
}

void MeasureTripletStart(const Reconstruction& tracks, const std::map<uint32_t, Pose>& initial,
                         const std::vector<LocalMotion>& triplets, const LocalMotionOptions& options,
                         PreparedHessians* hessians) {
  hessians->triplet_rotation_misfit = TripletRotationMisfit(tracks, initial, triplets);
  const bool far = hessians->triplet_rotation_misfit > options.triplet_start_misfit;
  PGBA_LOG_DEBUG << "local motions: initial poses " << hessians->triplet_rotation_misfit
                << " triplet residuals off their triplets' rotations"
                << (far ? ": linearised at the triplets' pointless BA instead" : "");
  if (far)
    hessians->linearization_poses = TripletPointlessStart(tracks, initial, triplets, options.triplet_start_max_iterations,
                                                          options.triplet_start_max_per_image);
}

PreparedHessians PrepareLocalHessians(const Reconstruction& tracks, const std::map<uint32_t, Pose>& initial,
                                      const std::vector<LocalMotion>& triplets, const RefinementOptions& options) {
  ResetPeakRss();
  Timer timer;
  PreparedHessians out;
  std::map<uint32_t, Pose> start = initial;
  if (NeedsConvergedStart(options.local_motions)) {
    // N-view motions start where the triplets' pointless BA ends: the initial poses are too
    // far from the local optima of long motions (local_motions.h). Images that BA leaves out
    // keep their initial pose, so that the motions are chosen over the same images as from
    // a workspace's initial poses (ChooseLocalMotions).
    PGBA_LOG_DEBUG << "local motions: the triplets' pointless BA gives the motions their starting poses";
    LocalHessianResult triplet_hessians = ComputeLocalHessians(tracks, triplets, options.local_hessian);
    const GlobalBAResult refined = RelinearizedGlobalBA(tracks, options.local_hessian, initial, triplets,
                                                        std::move(triplet_hessians.hessians), options.global_ba);
    for (const auto& [id, pose] : refined.poses) start[id] = pose;
  } else if (options.local_motions.kind == MotionKind::kWholeTracks && options.local_motions.triplet_start_misfit > 0) {
    MeasureTripletStart(tracks, initial, triplets, options.local_motions, &out);
    if (out.triplet_start()) start = out.linearization_poses;
  }
  out.motions = BuildLocalMotions(tracks, start, triplets, options.local_hessian, options.local_motions);
  const FreeIntrinsics free = SelectRefinedIntrinsics(tracks, options);
  out.result = ComputeLocalHessians(tracks, out.motions, options.local_hessian, nullptr, free.empty() ? nullptr : &free);
  out.seconds = timer.Seconds();
  out.peak_rss_mb = PeakRssMb();
  return out;
}

nlohmann::json IntrinsicsRecord(uint32_t id, const Camera& camera, const std::vector<int>& free,
                                const Eigen::VectorXd& initial, const Eigen::VectorXd& final_values,
                                const Eigen::VectorXd& stddev) {
  nlohmann::json params = nlohmann::json::array();
  const Eigen::MatrixXd directions = IntrinsicDirections(camera, free);
  for (size_t i = 0; i < free.size(); ++i) {
    // An unknown that moves more than its own parameter is the focal with fy / fx held.
    std::string name = IntrinsicParamName(camera.model, free[i]);
    if ((directions.col(static_cast<int>(i)).array() != 0.0).count() > 1) name += " (fy / fx held)";
    params.push_back({{"index", free[i]},
                      {"name", name},
                      {"initial", initial(i)},
                      {"final", final_values(i)},
                      {"stddev", stddev.size() > static_cast<int>(i) ? NumberOrNull(stddev(i)) : nlohmann::json()}});
  }
  return {{"camera_id", id}, {"model", CameraModelName(camera.model)}, {"params", params},
          {"final_params", camera.params}};
}

void CheckRefinedCameras(const RefinementResult& r) {
  for (const auto& [id, camera] : r.cameras)  // a distortion estimated past invertibility, a focal <= 0
    if (const std::string problem = camera.Validate(); !problem.empty())
      throw InputError("self-calibration: the intrinsics estimated for camera " + std::to_string(id) +
                       " are unusable (" + problem +
                       "); hold them with intrinsics.cameras = \"none\" or intrinsics.refine_extra_params = false");
}

void LogRefinement(const char* method, const RefinementResult& r) {
  PGBA_LOG_DEBUG << method << ": " << r.poses.size() << " poses, " << r.num_params << " unknowns, " << r.iterations
                << " iterations, adjustment " << r.adjust_seconds << " s (preparation " << r.prepare_seconds << " s)";
}

namespace {

// The parts a global BA on the motions `hessians` fills.
RefinementResult RefinementOfGlobalBA(const Reconstruction& tracks, const PreparedHessians& hessians,
                                     const RefinementOptions& options, const GlobalBAResult& g) {
  RefinementResult r;
  r.prepare_seconds = hessians.seconds;
  r.adjust_seconds = g.summary.seconds;
  r.peak_rss_mb = std::max(PeakRssMb(), hessians.peak_rss_mb);
  r.poses = g.poses;
  r.excluded_images = g.summary.excluded_images;
  if (!g.intrinsics.empty()) {
    r.cameras = tracks.cameras;
    for (const auto& [id, k] : g.intrinsics) {
      ScatterIntrinsics(k.values, k.free, &r.cameras.at(id));
      r.intrinsics.push_back(IntrinsicsRecord(id, r.cameras.at(id), k.free, k.initial, k.values, k.stddev));
    }
  }
  r.num_params = g.summary.num_params;
  r.iterations = g.summary.iterations;
  r.details = {{"motion_kind", options.local_motions.kind},
               {"motions", hessians.motions.size()},
               {"triplets_used", g.summary.num_motions},
               {"triplets_excluded", g.summary.num_motions_excluded},
               {"triplets_downweighted", g.summary.num_motions_downweighted},
               {"rounds", g.summary.rounds},
               {"fitting_scale", g.summary.robust_scale},
               {"local_hessians", LocalHessianStatusCounts(hessians.result)}};
  return r;
}

}  // namespace

RefinementResult RefineOnMotions(const char* method, const Reconstruction& tracks,
                                 const std::map<uint32_t, Pose>& initial, const PreparedHessians& hessians,
                                 const RefinementOptions& options, bool record_history, const MotionGlobalBA& adjust) {
  ResetPeakRss();
  std::vector<std::map<uint32_t, Pose>> history;
  GlobalBAIterationCallback callback;
  if (record_history) callback = [&history](const GlobalBAIteration& it) { history.push_back(*it.poses); };
  // Far from the triplets the motions were linearised at the triplets' pointless BA, which is
  // where the global BA starts too.
  const std::map<uint32_t, Pose>& start = hessians.triplet_start() ? hessians.linearization_poses : initial;
  RefinementResult r = RefinementOfGlobalBA(tracks, hessians, options, adjust(start, callback));
  r.history = std::move(history);
  CheckRefinedCameras(r);
  LogRefinement(method, r);
  return r;
}

namespace {

// RefinePointless on `models`, the local Hessians of `hessians` (a copy, or handed over).
RefinementResult RefinePointlessOn(const Reconstruction& tracks, const std::map<uint32_t, Pose>& initial,
                                   const PreparedHessians& hessians, std::vector<LocalHessian> models,
                                   const RefinementOptions& options, bool record_history, const GcpInput* gcps) {
  // The local Hessians re-linearised at the solution until converged (global_ba.h); their
  // passes count as adjustment time.
  const GlobalBAOptions& pointless = options.global_ba;
  GlobalBASummary summary;
  RefinementResult r = RefineOnMotions(
      "pointless", tracks, initial, hessians, options, record_history,
      [&](const std::map<uint32_t, Pose>& start, const GlobalBAIterationCallback& callback) {
        GlobalBAResult g = RelinearizedGlobalBA(tracks, options.local_hessian, start, hessians.motions,
                                                std::move(models), pointless, callback, gcps);
        summary = g.summary;
        return g;
      });
  r.details["misfit_ratio_initial"] = NumberOrNull(summary.misfit_ratio_initial);
  r.details["misfit_ratio"] = NumberOrNull(summary.misfit_ratio);
  r.details["relinearizations"] = summary.relinearizations;
  r.details["converged"] = summary.converged;
  r.details["stop_reason"] = summary.stop_reason;
  nlohmann::json passes = nlohmann::json::array();
  for (const GlobalBASummary::Pass& p : summary.passes)
    passes.push_back({{"robust_cost", NumberOrNull(p.robust_cost)},
                      {"kept", p.kept},
                      {"displacement_sigmas", NumberOrNull(p.displacement)},
                      {"outlier_px", p.outlier_px}});
  r.details["passes"] = std::move(passes);
  r.details["start_median_px"] = summary.start_median_px;
  r.details["start_outlier_px"] = summary.start_outlier_px;
  r.details["relinearization_seconds"] = summary.relinearization_seconds;
  r.details["triplet_rotation_misfit"] = hessians.triplet_rotation_misfit;
  r.details["triplet_start"] = hessians.triplet_start();
  if (gcps) r.details["gcp_residuals"] = summary.num_gcp_residuals;
  return r;
}

}  // namespace

RefinementResult RefinePointless(const Reconstruction& tracks, const std::map<uint32_t, Pose>& initial,
                                 const PreparedHessians& hessians, const RefinementOptions& options,
                                 bool record_history, const GcpInput* gcps) {
  return RefinePointlessOn(tracks, initial, hessians, hessians.result.hessians, options, record_history, gcps);
}

RefinementResult RefinePointlessReleasing(const Reconstruction& tracks, const std::map<uint32_t, Pose>& initial,
                                          PreparedHessians* hessians, const RefinementOptions& options,
                                          bool record_history, const GcpInput* gcps) {
  std::vector<LocalHessian> models = std::move(hessians->result.hessians);
  hessians->result.hessians.clear();
  hessians->released = true;
  return RefinePointlessOn(tracks, initial, *hessians, std::move(models), options, record_history, gcps);
}

std::string PointBasedOptions::Check() const {
  if (const std::string m = CheckRanges(*this, "point_based"); !m.empty()) return m;
  return "";
}

// The sections' own Check()s, each message prefixed with its section.
std::string RefinementOptions::Check() const {
  if (const std::string p = local_motions.Check(); !p.empty()) return "local_motions." + p;
  if (const std::string p = local_hessian.Check(); !p.empty()) return "local_hessian." + p;
  if (const std::string p = global_ba.Check(); !p.empty()) return "global_ba." + p;
  if (const std::string p = point_based.Check(); !p.empty()) return "point_based." + p;
  if (const std::string p = intrinsics.Check(); !p.empty()) return "intrinsics." + p;
  return "";
}

}  // namespace pgba
