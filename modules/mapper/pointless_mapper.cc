#include "mapper/pointless_mapper.h"

#include <algorithm>
#include <cstdio>
#include <optional>
#include <stdexcept>
#include <utility>

#include "mapper/dropped_images.h"
#include "pgba/scene/triangulate_model.h"
#include "pgba/util/error.h"
#include "pgba/util/logging.h"
#include "pgba/util/text_format.h"
#include "triplets/triplets.h"

namespace pgba {

std::string PointlessMapperOptions::Check() const {
  if (const std::string p = mapper.Check(); !p.empty()) return p;
  if (const std::string p = refinement.Check(); !p.empty()) return p;
  if (const std::string p = gcp.Check(); !p.empty()) return "gcp." + p;
  if (const std::string p = convergence.Check(); !p.empty()) return "convergence." + p;
  if (const std::string p = verification.Check(); !p.empty()) return p;
  return "";
}

void AddPointlessMapperSections(ConfigSchema* schema) {
  AddGlobalMapperSections(schema);
  AddRefinementSections(schema);
  schema->Add("gcp", GcpOptions{});
  schema->Add("convergence", ConvergenceOptions{});
  schema->Add("verification", ImageVerificationOptions{});
}

void ReadPointlessMapperOptions(const Config& config, PointlessMapperOptions* options) {
  ReadGlobalMapperOptions(config, &options->mapper);
  ReadRefinementOptions(config, &options->refinement);
  ReadSection(config, "gcp", &options->gcp);
  ReadSection(config, "convergence", &options->convergence);
  ReadSection(config, "verification", &options->verification);
  if (const std::string problem = options->Check(); !problem.empty()) ThrowInputError(config.origin(), 0, problem);
}

namespace {

// Step 1 (and 2, again with new focals): the verified pairs of `tracks` with its cameras, from
// the front end's geometries where given.
std::vector<TwoViewGeometry> VerifyPairs(const Reconstruction& tracks, const PairOptions& options, Report* report,
                                         const char* stage, const std::vector<TwoViewGeometry>* front_end) {
  StageTimer timer(report, stage);
  PairStats stats;
  std::vector<TwoViewGeometry> pairs = EstimatePairs(tracks, options, &stats, front_end);
  timer.Stop().update(ToJson(stats));
  if (pairs.empty())
    throw InputError(std::string(stage) == "pairs"
                         ? "tracks: no image pair could be verified (too few shared tracks?)"
                         : "tracks: no image pair could be verified with the focals from the view graph");
  return pairs;
}

// Step 2: focals of the cameras without a prior focal, from the verified pairs.
void EstimateFocals(const Reconstruction& tracks, const ViewGraphCalibrationOptions& options, Report* report,
                    GlobalMapperResult* result) {
  const bool any = std::any_of(tracks.cameras.begin(), tracks.cameras.end(), [&](const auto& entry) {
    return options.cameras == FocalEstimationCameras::kAll ||
           (options.cameras == FocalEstimationCameras::kWeakPrior && !entry.second.has_prior_focal_length);
  });
  if (!any) return;
  StageTimer timer(report, "focal_estimation");
  result->calibration = CalibrateFocalsFromViewGraph(tracks, result->pairs, options, &result->cameras);
  timer.Stop().update(result->calibration.ToJson());
  for (const CameraFocalEstimate& c : result->calibration.cameras) {
    char line[256];
    std::snprintf(line, sizeof(line), "camera %u: focal %.1f px -> %.1f px (sd %.2g%%, from %d image pairs)",
                  c.camera_id, c.prior_focal, c.estimated_focal, 100 * c.relative_sd, c.pairs_used);
    if (c.applied) {
      PGBA_LOG_INFO << "focal from the image pairs: " << line;
    } else {
      PGBA_LOG_WARN << "focal of camera " << c.camera_id << " not taken from the image pairs (" << c.reason
                    << "): the run goes on from " << FormatNumber("%.1f", c.prior_focal)
                    << " px (a calibration file or an EXIF focal gives a better start)";
      PGBA_LOG_DEBUG << "focal from the image pairs: " << line;
    }
  }
}

// Step 3: the triplets, each solved by its own BA.
std::vector<LocalMotion> EstimateTriplets(const Reconstruction& tracks, const std::vector<TwoViewGeometry>& pairs,
                                      const TripletOptions& options, Report* report) {
  StageTimer timer(report, "triplets");
  TripletStats stats;
  std::vector<LocalMotion> triplets = BuildTriplets(tracks, pairs, options, &stats);
  timer.Stop().update(ToJson(stats));  // BuildTriplets logs its own summary line
  if (triplets.empty()) throw InputError("tracks: no triplet survived estimation (see report.json for reasons)");
  return triplets;
}

// Step 4: rotation and translation averaging over the triplets; each kept triplet gets its
// global->local similarity. With `outliers` (the sensitivity experiment) the relative rotations
// averaged are corrupted first.
GlobalInitResult AverageMotions(const Reconstruction& tracks, const std::vector<TwoViewGeometry>& pairs,
                                const std::vector<LocalMotion>& triplets, const GlobalInitOptions& options,
                                const OutlierInjectionOptions& outliers, Report* report,
                                OutlierInjectionResult* injected) {
  StageTimer timer(report, "global_init");
  GlobalInitResult init;
  if (outliers.fraction > 0.0) {
    const CorruptedRelativeMotions c = CorruptRelativeMotions(outliers, pairs, triplets);
    *injected = c.injected;
    PGBA_LOG_INFO << "outlier injection: " << c.injected.pairs.size() << " pairs and " << c.injected.triplets.size()
                  << (outliers.triplet_corruption == TripletCorruption::kLocalPoses ? " triplets (local poses)"
                                                                                   : " triplets (their relative rotations)")
                  << " given random rotations";
    init = RunGlobalInitialisation(tracks, c.pairs, c.triplets, options, &c.rotation_measurements);
  } else {
    init = RunGlobalInitialisation(tracks, pairs, triplets, options);
  }
  nlohmann::json& stage = timer.Stop();
  stage.update(GlobalInitReport(init));
  stage["outliers_injected"] = {{"pairs", injected->pairs.size()}, {"triplets", injected->triplets.size()}};
  if (!init.success) throw InputError("tracks: global initialisation failed: " + init.message);
  (*report)["images_input"] = tracks.images.size();
  (*report)["images_registered"] = init.poses.size();
  (*report)["images_dropped"] = init.images_dropped;
  PGBA_LOG_INFO << "initial poses (rotation and translation averaging): " << init.poses.size() << " of "
                << tracks.images.size() << " images"
                << (init.images_dropped.empty() ? "" : " (the others are listed at the end)") << ", from "
                << init.triplets.size() << (init.triplets.size() == 1 ? " triplet" : " triplets") << " agreeing to "
                << FormatNumber("%.2g", init.stats.rotation.residual_median_deg) << " deg (median), "
                << FormatNumber("%.1f", stage["seconds"].get<double>()) << " s";
  return init;
}

// Step 5: the relative motions and their local Hessians.
PreparedHessians ComputeMotionHessians(const Reconstruction& tracks, const GlobalInitResult& init,
                                       const RefinementOptions& options, Report* report) {
  StageTimer timer(report, "local_hessians");
  PreparedHessians h = PrepareLocalHessians(tracks, init.poses, init.triplets, options);
  nlohmann::json& stage = timer.Stop();
  stage["triplets"] = init.triplets.size();
  stage["motions"] = h.motions.size();
  stage["ok"] = h.result.num_ok();
  stage["rejected"] = LocalHessianStatusCounts(h.result);
  stage["rejected"].erase(LocalHessianStatusName(LocalHessianStatus::kOk));
  stage["triplet_rotation_misfit"] = h.triplet_rotation_misfit;
  stage["triplet_start"] = h.triplet_start();
  return h;
}

// Step 6: with a GCP file, the initial solution moved into the GCP frame.
std::optional<GcpInput> TransferToGcpFrame(const Reconstruction& tracks, const PointlessMapperOptions& options,
                                           Report* report, GlobalInitResult* init) {
  if (options.gcp_path.empty()) return std::nullopt;
  StageTimer timer(report, "gcp_alignment");
  GcpInput gcps = LoadGcps(options.gcp_path, tracks, options.gcp);
  const GcpAlignment a = AlignToGcps(gcps, &init->poses, &init->triplets);
  nlohmann::json& stage = timer.Stop();
  stage["file"] = options.gcp_path;
  stage["gcps"] = gcps.gcps.size();
  stage["gcps_triangulated"] = a.num_gcps_used;
  stage["gcps_dropped"] = a.dropped;
  stage["scale"] = a.transform.s;
  stage["rms_m"] = a.rms_before;
  return gcps;
}

// Step 7: the pointless global BA from the initial poses on the local Hessians.
RefinementResult AdjustPointless(const Reconstruction& tracks, const GlobalInitResult& init,
                                 const PreparedHessians& hessians, const PointlessMapperOptions& options,
                                 const GcpInput* gcps, Report* report) {
  StageTimer timer(report, "global_ba");
  RefinementResult refined =
      RefinePointless(tracks, init.poses, hessians, options.refinement, options.record_convergence, gcps);
  nlohmann::json& stage = timer.Stop();
  stage["params"] = refined.num_params;
  stage["iterations"] = refined.iterations;
  stage["adjust_seconds"] = refined.adjust_seconds;
  stage.update(refined.details);
  stage.erase("local_hessians");
  if (!refined.cameras.empty()) {
    (*report)["intrinsics"] = refined.intrinsics;
    // One line per camera, each parameter by name: pixels (f, cx, cy) to 0.01 px, the
    // distortion to 4 significant digits, the standard deviation to 2.
    for (const nlohmann::json& camera : refined.intrinsics) {
      std::string line;
      for (const nlohmann::json& p : camera["params"]) {
        const std::string name = p.value("name", "?");
        const bool pixels = name[0] == 'f' || name[0] == 'c';
        const char* format = pixels ? "%.2f" : "%.4g";
        const auto value = [&](const char* key) {
          return p[key].is_number() ? FormatNumber(format, p[key].get<double>()) : std::string("?");
        };
        line += (line.empty() ? "" : ", ") + name + " " + value("initial") + " -> " + value("final") +
                (pixels ? " px" : "") +
                (p["stddev"].is_number() ? " (sd " + FormatNumber("%.2g", p["stddev"].get<double>()) + ")" : "");
      }
      PGBA_LOG_INFO << "camera " << camera.value("camera_id", 0u) << " (" << camera.value("model", "")
                    << ") self-calibrated: " << line;
    }
  }
  return refined;
}

// After step 7 with GCPs: the GCPs triangulated with the final poses vs their coordinates.
void CheckFinalGcps(const GcpInput& gcps, const std::map<uint32_t, Pose>& poses, Report* report) {
  StageTimer timer(report, "gcp_check");
  const GcpCheck check = CheckGcps(gcps, poses);
  timer.Stop().update(check.ToJson());
  PGBA_LOG_INFO << "GCPs with the final poses: " << check.num_gcps << " triangulated, RMS " << check.rms << " m, max "
                << check.max << " m";
}

// Step 8: every registered image verified; the failing ones registered again or dropped.
void VerifyImages(const Reconstruction& tracks, const std::vector<TwoViewGeometry>& pairs,
                  const ImageVerificationOptions& options, Report* report, PointlessMapperResult* r) {
  if (!options.enabled) return;
  StageTimer timer(report, "verification");
  const Reconstruction calibrated = r->refined.cameras.empty() ? Reconstruction() : TracksWithCameras(tracks, r->refined.cameras);
  const Reconstruction& t = r->refined.cameras.empty() ? tracks : calibrated;
  r->verification = VerifyRegisteredImages(t, pairs, r->refined.poses, options);
  timer.Stop().update(r->verification.ToJson(tracks));
  r->refined.poses = r->verification.poses;
  const ImageVerificationResult& v = r->verification;
  PGBA_LOG_INFO << "verification: " << v.verdicts.size() - v.num_reregistered - v.num_dropped << " of "
                << v.verdicts.size() << " images agree with their observations and verified pairs"
                << (v.num_reregistered ? ", " + std::to_string(v.num_reregistered) + " registered again" : "")
                << (v.num_dropped ? ", " + std::to_string(v.num_dropped) + " dropped" : "");
  for (const ImageVerdict& d : v.verdicts) {
    const std::string& name = tracks.images.at(d.image_id).name;
    if (d.status == ImageVerdictStatus::kReregistered)
      PGBA_LOG_WARN << "image " << name << " registered again from the structure (moved " << d.moved_deg
                    << " deg): its adjusted pose failed verification: " << d.reason;
    else if (d.status == ImageVerdictStatus::kDropped)
      PGBA_LOG_WARN << "image " << name << " dropped: " << d.reason;
  }
}

// Step 9: every track triangulated with the final poses (and the refined intrinsics).
Reconstruction Triangulate(const Reconstruction& tracks, const RefinementResult& refined, Report* report) {
  StageTimer timer(report, "triangulation");
  Reconstruction model = refined.cameras.empty() ? TriangulateModel(tracks, refined.poses)
                                                 : TriangulateModel(TracksWithCameras(tracks, refined.cameras),
                                                                    refined.poses);
  nlohmann::json& stage = timer.Stop();
  stage["points"] = model.points3D.size();
  PGBA_LOG_INFO << "points: " << model.points3D.size() << " of " << tracks.points3D.size()
                << " tracks triangulated (2 or more registered images agree on each), "
                << FormatNumber("%.1f", stage["seconds"].get<double>()) << " s";
  return model;
}

// The images of the result and the ones left out on the way (report keys).
void RecordImages(const Reconstruction& tracks, const PointlessMapperResult& r, Report* report) {
  std::vector<std::string> dropped = r.initial.init.images_dropped;
  for (uint32_t id : r.refined.excluded_images) dropped.push_back(tracks.images.at(id).name);
  for (const ImageVerdict& v : r.verification.verdicts)
    if (v.status == ImageVerdictStatus::kDropped) dropped.push_back(tracks.images.at(v.image_id).name);
  // The commands print the list once, at their end (a run may reconstruct twice).
  const std::string summary = DroppedImagesSummary(DroppedImages(tracks, r), tracks.images.size());
  if (!summary.empty()) PGBA_LOG_DEBUG << summary;
  (*report)["images_input"] = tracks.images.size();
  (*report)["images_registered"] = r.refined.poses.size();
  (*report)["images_dropped"] = dropped;
  (*report)["params"] = r.refined.num_params;
}

}  // namespace

PointlessMapper::PointlessMapper(PointlessMapperOptions options) : options_(std::move(options)) {
  if (const std::string problem = options_.Check(); !problem.empty())
    throw std::invalid_argument("PointlessMapper: " + problem);
}

PointlessMapperResult PointlessMapper::Solve(const Reconstruction& input, Report* report, PointlessMapperResult r,
                                             const std::vector<TwoViewGeometry>* front_end) const {
  const GlobalMapperOptions& o = options_.mapper;
  // The tracks with the cameras of step 2 (a copy only when a focal changed).
  std::optional<Reconstruction> recalibrated;
  const auto tracks = [&]() -> const Reconstruction& { return recalibrated ? *recalibrated : input; };
  if (!r.initial.init.success) {
    if (input.images.size() < 3)
      throw InputError("tracks: at least 3 images are needed, got " + std::to_string(input.images.size()));
    r.initial.cameras = input.cameras;
    // 1. View graph: the verified image pairs.
    r.initial.pairs = VerifyPairs(input, o.pairs, report, "pairs", front_end);
    // 2. Focals from the view graph; with a new focal the pairs are verified again (the front
    //    end's geometries do not hold for the new bearings).
    EstimateFocals(input, o.calibration, report, &r.initial);
    if (CamerasChanged(input, r.initial.cameras)) {
      recalibrated = TracksWithCameras(input, r.initial.cameras);
      r.initial.pairs = VerifyPairs(tracks(), o.pairs, report, "pairs_recalibrated", nullptr);
    }
    // 3. Triplets, each solved by its own BA. Self-calibration reaches back to it: a
    //    calibration that is only a prior bends the relative motions the averaging starts from.
    TripletOptions triplet_options = o.triplets;
    if (!options_.skip_refinement && !SelectRefinedIntrinsics(input, options_.refinement).empty())
      triplet_options.refine_intrinsics = true;
    const std::vector<LocalMotion> triplets = EstimateTriplets(tracks(), r.initial.pairs, triplet_options, report);
    // 4. Rotation and translation averaging: the initial poses.
    r.initial.init = AverageMotions(tracks(), r.initial.pairs, triplets, o.global_init, o.rotation_outliers, report,
                                    &r.initial.outliers_injected);
  } else if (CamerasChanged(input, r.initial.cameras)) {
    recalibrated = TracksWithCameras(input, r.initial.cameras);
  }
  if (options_.skip_refinement) return r;

  // 5. Relative motions and their local Hessians.
  if (r.hessians.motions.empty()) r.hessians = ComputeMotionHessians(tracks(), r.initial.init, options_.refinement, report);
  // 6. GCPs: the initial solution in their frame.
  const std::optional<GcpInput> gcps = TransferToGcpFrame(tracks(), options_, report, &r.initial.init);
  // 7. Pointless global BA, re-linearised at its solution.
  r.refined = AdjustPointless(tracks(), r.initial.init, r.hessians, options_, gcps ? &*gcps : nullptr, report);
  if (gcps) CheckFinalGcps(*gcps, r.refined.poses, report);
  if (options_.record_convergence) {
    StageTimer timer(report, "convergence");
    r.convergence = EvaluateConvergence(tracks(), r.refined.history, options_.convergence);
    timer.Stop().update(r.convergence.ToJson());
  }
  r.refined.history.clear();
  // 8. Every registered image verified; a failing one registered again or dropped.
  VerifyImages(tracks(), r.initial.pairs, options_.verification, report, &r);
  // 9. Points triangulated with the final poses.
  r.model = Triangulate(tracks(), r.refined, report);
  RecordImages(tracks(), r, report);
  return r;
}

GlobalMapperResult RunGlobalMapper(const Reconstruction& tracks, const GlobalMapperOptions& options, Report* report,
                                   const std::vector<TwoViewGeometry>* front_end) {
  PointlessMapperOptions initial_only;
  initial_only.mapper = options;
  initial_only.skip_refinement = true;
  return PointlessMapper(initial_only).Solve(tracks, report, {}, front_end).initial;
}

}  // namespace pgba
