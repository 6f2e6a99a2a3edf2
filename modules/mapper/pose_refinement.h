// The final adjustment of the initial global solution (paper steps 3 and 4; PointlessMapper
// steps 5 and 7): the local Hessians of the relative motions (section 3, eqs. 1-3; by default
// whole-track motions taken at the initial poses, local_motions.h), then the pointless global
// BA weighted by their (6N + K) x (6N + K) reduced camera matrices (eq. 5), re-linearised at
// its solution until the true reprojection cost has converged (global_ba.h). Its options (the
// config sections of the refinement, the point-based baseline's included, so that one preset
// serves `reconstruct` and `benchmark`) and its result; the baselines `pgba benchmark`
// compares it with are benchmark/baselines.h.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "global_ba/global_ba.h"
#include "local_hessian/local_hessian.h"
#include "local_hessian/local_motions.h"
#include "pgba/io/json_config.h"
#include "pgba/optim/bundle_adjuster.h"
#include "pgba/scene/reconstruction.h"
#include "pgba/scene/view_graph.h"

namespace pgba {

struct PointBasedOptions {
  // The final adjustment (Huber at 1 px: the robust loss the local Hessians use).
  BundleAdjusterOptions bundle;
  // Robust loss of the first pass, the one that still sees the gross outliers ("" = the
  // same as bundle.loss). Cauchy by default: Huber's linear tail gives every outlier of
  // hundreds of px a constant pull, and on a block with a weak mode (the planar video) those
  // pulls add up and hold the poses in a wrong minimum (0.62 px against 0.578 px, 0.9 deg)
  // that filtering no longer undoes. A redescending loss lets them go (tests/optim/
  // bundle_adjuster_test.cc); the second pass then runs the configured loss on the inliers.
  std::string first_pass_loss = "cauchy";
  // Observations whose reprojection error exceeds this after the first pass are removed and
  // the adjustment is run again (COLMAP's filter-and-refine; <= 0: a single pass).
  double filter_max_error_px = 4.0;
  // Empty when valid, else one line naming the first field out of its valid range (the
  // ranges of io/option_ranges.cc) or breaking a rule between fields.
  std::string Check() const;
};
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(PointBasedOptions, bundle, first_pass_loss, filter_max_error_px)

// One options struct per stage, each read from the config section of the same name.
struct RefinementOptions {
  LocalMotionOptions local_motions;                                      // section "local_motions"
  LocalHessianOptions local_hessian;                                     // section "local_hessian"
  GlobalBAOptions global_ba;                                             // section "global_ba"
  PointBasedOptions point_based;                                         // section "point_based"
  // Self-calibration (paper, "Self-calibrating bundle adjustment"): the intrinsic unknowns of
  // every adjustment (local Hessians, pointless global BA, point-based BA).
  IntrinsicsOptions intrinsics;                                          // section "intrinsics"
  // Whether the tracks' calibration is only a prior (set by `pgba run` when no calibration
  // file was given; IntrinsicsCameras::kAuto refines exactly then). Not a config key.
  bool calibration_is_prior = false;
  // Empty when valid, else one line naming the first field out of its valid range (the
  // ranges of io/option_ranges.cc) or breaking a rule between fields.
  std::string Check() const;
};
// The intrinsic unknowns `options` gives the cameras of `tracks` (empty: none).
FreeIntrinsics SelectRefinedIntrinsics(const Reconstruction& tracks, const RefinementOptions& options);
void AddRefinementSections(ConfigSchema* schema);
void ReadRefinementOptions(const Config& config, RefinementOptions* options);

struct RefinementResult {
  std::map<uint32_t, Pose> poses;  // refined poses (images the method could adjust)
  std::vector<uint32_t> excluded_images;  // initial poses the method could not adjust
  // With self-calibration: the refined cameras (the tracks' cameras with the estimated
  // intrinsics; empty when none were estimated), and per camera {free indices, initial,
  // final, stddev} for report.json.
  std::map<uint32_t, Camera> cameras;
  nlohmann::json intrinsics = nlohmann::json::array();
  int num_params = 0;   // unknowns: 6 per pose + 7 per triplet, or + 3 per point
  int iterations = 0;   // Levenberg-Marquardt iterations (all rounds / passes)
  // Wall time of the preparation (local Hessians; point triangulation) and of the
  // adjustment alone, and the peak resident memory over both (MiB).
  double prepare_seconds = 0.0;
  double adjust_seconds = 0.0;
  double peak_rss_mb = 0.0;
  // Poses before the first and after every iteration (if requested): the convergence curve.
  std::vector<std::map<uint32_t, Pose>> history;
  nlohmann::json details = nlohmann::json::object();  // method-specific counts
};

// The relative motions (the triplets, or N-view motions built from the initial poses:
// options.local_motions) and their local Hessians, shared by pointless and averaging (the
// benchmark computes them once). Logged and counted per rejection reason. `seconds` covers
// both (building N-view motions includes their local BAs).
struct PreparedHessians {
  std::vector<LocalMotion> motions;
  LocalHessianResult result;  // one per motion
  double seconds = 0.0;
  double peak_rss_mb = 0.0;
  // Whole-track motions: TripletRotationMisfit of the initial poses.
  double triplet_rotation_misfit = 0.0;
  // When that misfit exceeded local_motions.triplet_start_misfit (linearization_start.h): the
  // poses the motions were linearised at (the triplets' pointless BA), where the pointless
  // global BA starts too, so that its first checked step is measured against the cost where
  // its models were taken. Empty otherwise.
  std::map<uint32_t, Pose> linearization_poses;
  // Whether the motions were linearised at the triplets' pointless BA (not the initial poses).
  bool triplet_start() const { return !linearization_poses.empty(); }
  // The local Hessians were handed to the global BA (RefinePointlessReleasing): result.hessians
  // is empty, its status counts stay.
  bool released = false;
};
PreparedHessians PrepareLocalHessians(const Reconstruction& tracks, const std::map<uint32_t, Pose>& initial,
                                      const std::vector<LocalMotion>& triplets, const RefinementOptions& options);
// Sets hessians->triplet_rotation_misfit from `initial`, and when it exceeds the threshold the
// linearization_poses (which also decide the global BA's start and passes: a workspace re-run
// reads them back from motions.json).
void MeasureTripletStart(const Reconstruction& tracks, const std::map<uint32_t, Pose>& initial,
                         const std::vector<LocalMotion>& triplets, const LocalMotionOptions& options,
                         PreparedHessians* hessians);

// Step 7: the pointless global BA from `initial` on `hessians` (from PrepareLocalHessians on
// the same initialisation), re-linearised at its solution (global_ba.h). With
// `record_history`, the poses before the first and after every iteration. Optional `gcps`:
// GCP residuals (`initial` already in the GCP frame, gcp_alignment.h). InputError when no
// usable motion is left or self-calibration estimated unusable intrinsics.
RefinementResult RefinePointless(const Reconstruction& tracks, const std::map<uint32_t, Pose>& initial,
                                 const PreparedHessians& hessians, const RefinementOptions& options,
                                 bool record_history = false, const GcpInput* gcps = nullptr);
// The same, the local Hessians handed over to the global BA, which re-takes them in place: one
// model per motion is held during the adjustment, not the caller's and the adjustment's
// (the largest memory of a large block). hessians->result.hessians is left empty and
// hessians->released set.
RefinementResult RefinePointlessReleasing(const Reconstruction& tracks, const std::map<uint32_t, Pose>& initial,
                                          PreparedHessians* hessians, const RefinementOptions& options,
                                          bool record_history = false, const GcpInput* gcps = nullptr);

// A global BA on the prepared motions, from `start`, reporting its iterations to `callback`
// (empty: none).
using MotionGlobalBA =
    std::function<GlobalBAResult(const std::map<uint32_t, Pose>& start, const GlobalBAIterationCallback& callback)>;
// Runs `adjust` from where `hessians` were linearised (the triplet start's poses, or
// `initial`), the poses of every iteration in the history with `record_history`, and fills the
// result (poses, refined cameras, counts, times; `method` in its log line). InputError as
// CheckRefinedCameras. The one runner of the pointless BA and the benchmark's Aver_BA.
RefinementResult RefineOnMotions(const char* method, const Reconstruction& tracks,
                                 const std::map<uint32_t, Pose>& initial, const PreparedHessians& hessians,
                                 const RefinementOptions& options, bool record_history, const MotionGlobalBA& adjust);
// Report rows of a camera's intrinsics: {camera_id, model, params: [{index, name, initial,
// final, stddev}], final_params} (stddev null where not computed).
nlohmann::json IntrinsicsRecord(uint32_t id, const Camera& camera, const std::vector<int>& free,
                                const Eigen::VectorXd& initial, const Eigen::VectorXd& final_values,
                                const Eigen::VectorXd& stddev);
// InputError if self-calibration left a camera unusable (a distortion past invertibility, a
// focal <= 0).
void CheckRefinedCameras(const RefinementResult& r);
// The one log line of a refinement method's result.
void LogRefinement(const char* method, const RefinementResult& r);

}  // namespace pgba
