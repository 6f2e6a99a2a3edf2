#include "mapper/pointless_mapper.h"

#include <algorithm>
#include <limits>
#include <map>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <utility>

#include "mapper/dropped_images.h"
#include "mapper/join_models.h"
#include "mapper/mapper_workspace.h"
#include "mapper/repeated_stages.h"
#include "local_hessian/local_hessian_io.h"
#include "pgba/io/workspace.h"
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
  if (const std::string p = components.Check(); !p.empty()) return "components." + p;
  return "";
}

void AddPointlessMapperSections(ConfigSchema* schema) {
  AddGlobalMapperSections(schema);
  AddRefinementSections(schema);
  schema->Add("gcp", GcpOptions{});
  schema->Add("convergence", ConvergenceOptions{});
  schema->Add("verification", ImageVerificationOptions{});
  schema->Add("components", ComponentJoiningOptions{});
}

void ReadPointlessMapperOptions(const Config& config, PointlessMapperOptions* options) {
  ReadGlobalMapperOptions(config, &options->mapper);
  ReadRefinementOptions(config, &options->refinement);
  ReadSection(config, "gcp", &options->gcp);
  ReadSection(config, "convergence", &options->convergence);
  ReadSection(config, "verification", &options->verification);
  ReadSection(config, "components", &options->components);
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

// Step 4: rotation and translation averaging over the triplets of each component of the
// triplet graph; each kept triplet gets its global->local similarity. With `outliers` (the
// sensitivity experiment) the relative rotations averaged are corrupted first. The models
// that succeed, largest first (at least one: InputError otherwise).
std::vector<GlobalInitResult> AverageMotions(const Reconstruction& tracks, const std::vector<TwoViewGeometry>& pairs,
                                             const std::vector<LocalMotion>& triplets,
                                             const GlobalInitOptions& options, const OutlierInjectionOptions& outliers,
                                             Report* report, OutlierInjectionResult* injected) {
  StageTimer timer(report, "global_init");
  std::vector<GlobalInitResult> models;
  if (outliers.fraction > 0.0) {
    const CorruptedRelativeMotions c = CorruptRelativeMotions(outliers, pairs, triplets);
    *injected = c.injected;
    PGBA_LOG_INFO << "outlier injection: " << c.injected.pairs.size() << " pairs and " << c.injected.triplets.size()
                  << (outliers.triplet_corruption == TripletCorruption::kLocalPoses ? " triplets (local poses)"
                                                                                   : " triplets (their relative rotations)")
                  << " given random rotations";
    models = InitialiseComponents(tracks, c.pairs, c.triplets, options, &c.rotation_measurements);
  } else {
    models = InitialiseComponents(tracks, pairs, triplets, options);
  }
  const GlobalInitResult& init = models.front();
  nlohmann::json& stage = timer.Stop();
  stage.update(GlobalInitReport(init));
  stage["outliers_injected"] = {{"pairs", injected->pairs.size()}, {"triplets", injected->triplets.size()}};
  stage["components"] = nlohmann::json::array();
  for (const GlobalInitResult& m : models) stage["components"].push_back(GlobalInitReport(m));
  if (!init.success) throw InputError("tracks: global initialisation failed: " + init.message);
  models.erase(std::remove_if(models.begin(), models.end(), [](const GlobalInitResult& m) { return !m.success; }),
               models.end());
  size_t placed = 0, num_triplets = 0;
  std::string sizes;
  for (const GlobalInitResult& m : models) {
    placed += m.poses.size();
    num_triplets += m.triplets.size();
    sizes += (sizes.empty() ? "" : " + ") + std::to_string(m.poses.size());
  }
  PGBA_LOG_INFO << "initial poses (rotation and translation averaging): " << placed << " of " << tracks.images.size()
                << " images" << (models.size() > 1 ? " in " + std::to_string(models.size()) + " models (" + sizes + ")" : "")
                << (placed < tracks.images.size() ? " (the others are listed at the end)" : "") << ", from "
                << num_triplets << (num_triplets == 1 ? " triplet" : " triplets") << " agreeing to "
                << FormatNumber("%.2g", init.stats.rotation.residual_median_deg) << " deg (median, largest model), "
                << FormatNumber("%.1f", stage["seconds"].get<double>()) << " s";
  return models;
}

// Step 4, continued: the largest model into `initial`, the others into `more`; the report's
// image counts over all of them.
void SplitModels(const Reconstruction& tracks, std::vector<GlobalInitResult> models, Report* report,
                 GlobalInitResult* initial, std::vector<ComponentModel>* more) {
  std::vector<std::string> dropped;
  size_t registered = 0;
  for (const auto& [id, image] : tracks.images) {
    const bool placed = std::any_of(models.begin(), models.end(), [&](const auto& m) { return m.poses.count(id); });
    registered += placed;
    if (!placed) dropped.push_back(image.name);
  }
  (*report)["images_input"] = tracks.images.size();
  (*report)["images_registered"] = registered;
  (*report)["images_dropped"] = dropped;
  *initial = std::move(models.front());
  more->clear();
  for (size_t m = 1; m < models.size(); ++m) more->push_back({std::move(models[m]), {}, {}, {}, {}});
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

// With options.workspace, step 5's artefacts written as soon as they are ready (the local
// Hessians are then handed to the global BA rather than kept for the output).
void WriteHessiansToWorkspace(const Reconstruction& tracks, const PointlessMapperOptions& options,
                              const PreparedHessians& hessians, Report* report) {
  if (options.workspace.empty()) return;
  StageTimer timer(report, "local_hessians_output");  // motions.json, local_hessians.json
  WriteLocalHessianWorkspace(options.workspace, tracks, hessians);
}

// An earlier adjustment restored after a failed one: the workspace's local Hessians are not its
// own, so they are removed (a run from the workspace computes them again).
void ForgetWorkspaceHessians(const PointlessMapperOptions& options) {
  if (options.workspace.empty()) return;
  std::error_code ignored;
  std::filesystem::remove(WorkspaceMotionsPath(options.workspace), ignored);
  std::filesystem::remove(WorkspaceLocalHessiansPath(options.workspace), ignored);
}

// Why the pointless BA's passes ended (GlobalBASummary::stop_reason), without the
// "wide_threshold_" of a run that ended in its wide-threshold phase (then *wide is set).
std::string StopReason(const RefinementResult& refined, bool* wide = nullptr) {
  static const std::string kWide = "wide_threshold_";
  std::string stop = refined.details.value("stop_reason", "");
  const bool in_wide = stop.compare(0, kWide.size(), kWide) == 0;
  if (in_wide) stop.erase(0, kWide.size());
  if (wide) *wide = in_wide;
  return stop;
}

// Step 7: the pointless global BA from the initial poses on the local Hessians.
// With options.workspace the local Hessians, on disk already, are handed to the adjustment.
RefinementResult AdjustPointless(const Reconstruction& tracks, const GlobalInitResult& init,
                                 PreparedHessians* hessians, const PointlessMapperOptions& options,
                                 const GcpInput* gcps, Report* report) {
  StageTimer timer(report, "global_ba");
  // Counted before the adjustment, which may release the local Hessians.
  const size_t motions = hessians->motions.size(), usable = hessians->result.num_ok();
  const double hessian_seconds = hessians->seconds;
  RefinementResult refined =
      options.workspace.empty()
          ? RefinePointless(tracks, init.poses, *hessians, options.refinement, options.record_convergence, gcps)
          : RefinePointlessReleasing(tracks, init.poses, hessians, options.refinement, options.record_convergence,
                                     gcps);
  nlohmann::json& stage = timer.Stop();
  stage["params"] = refined.num_params;
  stage["iterations"] = refined.iterations;
  stage["adjust_seconds"] = refined.adjust_seconds;
  stage.update(refined.details);
  stage.erase("local_hessians");
  // One line: the images and local adjustments that went in, whether it converged, how long
  // (the local adjustments' time is their own stage's).
  bool wide = false;
  const std::string stop = StopReason(refined, &wide);
  const std::string why = stop == "max_relinearizations" ? "global_ba.max_relinearizations passes reached"
                          : stop == "refused_step"       ? "a step raised the reprojection error"
                                                         : stop;
  PGBA_LOG_INFO << "global BA (pointless): " << refined.poses.size() << " images, on "
                << (usable < motions ? std::to_string(usable) + " of " : "") << motions << " local bundle "
                << (motions == 1 ? "adjustment" : "adjustments") << ", "
                << (stage.value("converged", false) ? "converged in "
                    : stop == "no_relinearization"
                        ? "one pass (global_ba.max_relinearizations 0) in "
                        : "not converged (" + why + (wide ? " at the start's wider outlier threshold" : "") +
                              ") after ")
                << refined.iterations << " iterations, " << FormatNumber("%.1f", stage["seconds"].get<double>())
                << " s (local adjustments " << FormatNumber("%.1f", hessian_seconds) << " s)";
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
                  const ImageVerificationOptions& options, Report* report, RefinementResult* refined,
                  ImageVerificationResult* verification) {
  if (!options.enabled) return;
  StageTimer timer(report, "verification");
  const Reconstruction calibrated = refined->cameras.empty() ? Reconstruction() : TracksWithCameras(tracks, refined->cameras);
  const Reconstruction& t = refined->cameras.empty() ? tracks : calibrated;
  *verification = VerifyRegisteredImages(t, pairs, refined->poses, options);
  timer.Stop().update(verification->ToJson(tracks));
  refined->poses = verification->poses;
  const ImageVerificationResult& v = *verification;
  PGBA_LOG_INFO << "verification: " << v.verdicts.size() - v.num_reregistered - v.num_dropped << " of "
                << v.verdicts.size() << " images agree with their observations and verified pairs"
                << (v.num_reregistered ? ", " + std::to_string(v.num_reregistered) + " registered again" : "")
                << (v.num_dropped ? ", " + std::to_string(v.num_dropped) + " dropped" : "");
  for (const ImageVerdict& d : v.verdicts) {
    const std::string& name = tracks.images.at(d.image_id).name;
    if (d.status == ImageVerdictStatus::kReregistered)
      PGBA_LOG_WARN << "image " << name << " registered again from the structure (moved " << d.moved_deg
                    << " deg): its adjusted pose failed verification: " << d.reason;
    else if (d.status == ImageVerdictStatus::kDropped)  // the commands list them at their end
      PGBA_LOG_DEBUG << "image " << name << " dropped: " << d.reason;
  }
}

// Step 7, continued: a pointless BA whose first step raised the reprojection cost kept its
// start, where the motions' quadratic models do not reach the optimum (a start too far from its
// triplets' relative rotations, linearization_start.h). The motions are then taken again where
// the triplets' pointless BA puts the poses (step 5 from there) and the BA solved again; the
// first round is kept in the report under "_before_triplet_start". Nothing is done when that
// start was taken already or local_motions.triplet_start_misfit turns it off.
void AdjustFromTheTripletsIfStuck(const Reconstruction& tracks, const GlobalInitResult& init,
                                  const PointlessMapperOptions& options, const GcpInput* gcps, Report* report,
                                  PreparedHessians* hessians, RefinementResult* refined, bool write_workspace) {
  // (Refused within the cost tolerance: the start is the minimum already.)
  const bool refused_first = StopReason(*refined) == "refused_step" &&
                             refined->details.value("relinearizations", 0) == 0 &&
                             !refined->details.value("converged", false);
  if (!refused_first) return;
  const LocalMotionOptions& motions = options.refinement.local_motions;
  if (hessians->triplet_start() || motions.kind != MotionKind::kWholeTracks || !(motions.triplet_start_misfit > 0)) {
    PGBA_LOG_WARN << "global BA: its first step raised the reprojection error: the " << refined->poses.size()
                  << " images keep the poses it started from; the verification checks them against their "
                     "observations";
    return;
  }
  PGBA_LOG_INFO << "global BA: its first step raised the reprojection error; the local motions are taken again "
                   "where the image triplets' own adjustment puts the poses";
  RenameStages(report, {"local_hessians", "local_hessians_output", "global_ba"}, "_before_triplet_start");
  PointlessMapperOptions from_triplets = options;
  from_triplets.refinement.local_motions.triplet_start_misfit = std::numeric_limits<double>::min();  // any misfit
  PreparedHessians again = ComputeMotionHessians(tracks, init, from_triplets.refinement, report);
  if (write_workspace) WriteHessiansToWorkspace(tracks, options, again, report);
  *refined = AdjustPointless(tracks, init, &again, from_triplets, gcps, report);
  *hessians = std::move(again);
}

// Whether the verification dropped an image or registered one again: the observations of
// such an image bent the adjustment of the others, which is then done again without them.
bool VerificationChanged(const ImageVerificationResult& v) { return v.num_dropped + v.num_reregistered > 0; }

// Step 8, continued: when the verification dropped an image or registered one again, the model
// adjusted again (steps 5 and 7) from the verified poses without the dropped images, and
// verified once more. An adjustment that fails (too few images left to it) leaves the first
// one standing, with the reason in the report.
void Readjust(const Reconstruction& tracks, const std::vector<TwoViewGeometry>& pairs,
              const PointlessMapperOptions& options, const GcpInput* gcps, Report* report, GlobalInitResult* init,
              PreparedHessians* hessians, RefinementResult* refined, ImageVerificationResult* verification,
              bool write_workspace) {
  if (!VerificationChanged(*verification) || refined->poses.empty()) return;
  PGBA_LOG_INFO << "adjusting again from the verified poses"
                << (verification->num_dropped ? ", without the " + std::to_string(verification->num_dropped) +
                                                    (verification->num_dropped == 1 ? " image" : " images") + " dropped"
                                              : std::string());
  const nlohmann::json stages = (*report)["stages"];
  RenameStages(report, {"local_hessians", "local_hessians_output", "global_ba", "verification"},
               "_before_readjustment");
  GlobalInitResult start = AdjustedStart(*init, refined->poses);
  try {
    PreparedHessians again = ComputeMotionHessians(tracks, start, options.refinement, report);
    if (write_workspace) WriteHessiansToWorkspace(tracks, options, again, report);
    RefinementResult adjusted = AdjustPointless(tracks, start, &again, options, gcps, report);
    adjusted.history.clear();
    ImageVerificationResult second;
    VerifyImages(tracks, pairs, options.verification, report, &adjusted, &second);
    KeepFirstVerdicts(*verification, &second);
    *init = std::move(start);
    *hessians = std::move(again);
    *refined = std::move(adjusted);
    *verification = std::move(second);
  } catch (const InputError& e) {
    // With no image left there is nothing to keep: the command's closing list names them all.
    internal::LogLine(refined->poses.empty() ? LogLevel::kDebug : LogLevel::kWarning)
        << (refined->poses.empty() ? "" : "warning: ")
        << "the adjustment again without the images the verification dropped failed, the first one is kept: "
        << e.what();
    if (write_workspace) ForgetWorkspaceHessians(options);
    (*report)["stages"] = stages;
    (*report)["stages"]["verification"]["readjustment_failed"] = e.what();
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
  // The commands print the images left out once, at their end (a run may reconstruct twice).
  const std::vector<DroppedImage> left_out = DroppedImages(tracks, r);
  const std::string summary = DroppedImagesSummary(left_out, tracks.images.size());
  if (!summary.empty()) PGBA_LOG_DEBUG << summary;
  const nlohmann::json fates = ImageFates(tracks, r, left_out);
  std::vector<std::string> dropped;
  size_t registered = 0;
  for (const nlohmann::json& f : fates) {
    if (f["model"].is_null()) {
      dropped.push_back(f["image"]);
    } else {
      ++registered;
    }
  }
  (*report)["images_input"] = tracks.images.size();
  (*report)["images_registered"] = registered;
  (*report)["images_dropped"] = dropped;
  (*report)["image_fates"] = fates;
  (*report)["params"] = r.refined.num_params;
  nlohmann::json models = nlohmann::json::array();
  const std::vector<const Reconstruction*> all = r.Models();
  for (size_t m = 0; m < all.size(); ++m) {
    size_t absolute = 0;
    for (const auto& [id, image] : all[m]->images) absolute += r.joining.joined.count(id);
    models.push_back({{"model", m},
                      {"images_registered", all[m]->images.size()},
                      {"by_absolute_pose", absolute},
                      {"points", all[m]->points3D.size()}});
  }
  (*report)["models"] = models;
}

// Steps 5 and 7-9 for a model beyond the largest, timed in `report`'s stage "more_models".
void AdjustModel(const Reconstruction& tracks, const std::vector<TwoViewGeometry>& pairs,
                 const PointlessMapperOptions& options, ComponentModel* m, nlohmann::json* record) {
  Report scratch;
  m->hessians = ComputeMotionHessians(tracks, m->init, options.refinement, &scratch);
  m->refined = AdjustPointless(tracks, m->init, &m->hessians, options, nullptr, &scratch);
  AdjustFromTheTripletsIfStuck(tracks, m->init, options, nullptr, &scratch, &m->hessians, &m->refined,
                               /*write_workspace=*/false);
  m->refined.history.clear();
  VerifyImages(tracks, pairs, options.verification, &scratch, &m->refined, &m->verification);
  Readjust(tracks, pairs, options, nullptr, &scratch, &m->init, &m->hessians, &m->refined, &m->verification,
           /*write_workspace=*/false);
  m->model = Triangulate(tracks, m->refined, &scratch);
  *record = {{"images", m->init.poses.size()},
             {"images_registered", m->refined.poses.size()},
             {"points", m->model.points3D.size()},
             {"stages", scratch.json()["stages"]}};
}

// Steps 7-9 of the largest model (its step 5 done, in the GCP frame with `gcps`), then steps
// 5 and 7-9 of the others (stage "more_models"); a smaller model that cannot be adjusted is
// dropped, its images named.
void AdjustModels(const Reconstruction& tracks, const std::vector<TwoViewGeometry>& pairs,
                  const PointlessMapperOptions& options, const GcpInput* gcps, Report* report,
                  PointlessMapperResult* r) {
  // 7. Pointless global BA, re-linearised at its solution.
  r->refined = AdjustPointless(tracks, r->initial.init, &r->hessians, options, gcps, report);
  AdjustFromTheTripletsIfStuck(tracks, r->initial.init, options, gcps, report, &r->hessians, &r->refined,
                               /*write_workspace=*/true);
  if (options.record_convergence) {
    StageTimer timer(report, "convergence");
    r->convergence = EvaluateConvergence(tracks, r->refined.history, options.convergence);
    timer.Stop().update(r->convergence.ToJson());
  }
  r->refined.history.clear();
  // 8. Every registered image verified; a failing one registered again or dropped, and then
  //    the model adjusted again (steps 5 and 7) from the verified poses.
  VerifyImages(tracks, pairs, options.verification, report, &r->refined, &r->verification);
  Readjust(tracks, pairs, options, gcps, report, &r->initial.init, &r->hessians, &r->refined, &r->verification,
           /*write_workspace=*/true);
  if (gcps) CheckFinalGcps(*gcps, r->refined.poses, report);
  // 9. Points triangulated with the final poses.
  r->model = Triangulate(tracks, r->refined, report);
  // Steps 5, 7 and 8 for the other models.
  if (r->more_models.empty()) return;
  StageTimer timer(report, "more_models");
  nlohmann::json records = nlohmann::json::array();
  std::vector<ComponentModel> adjusted;
  for (ComponentModel& m : r->more_models) {
    nlohmann::json record;
    PGBA_LOG_INFO << "another model: " << m.init.poses.size()
                  << " images that share no image pair with the largest, adjusted on their own";
    try {
      AdjustModel(tracks, pairs, options, &m, &record);
      adjusted.push_back(std::move(m));
    } catch (const InputError& e) {
      // A smaller model that cannot be adjusted leaves its images without a model; the
      // others stand.
      record = {{"images", m.init.poses.size()}, {"failed", e.what()}};
      for (const auto& [id, pose] : m.init.poses)
        r->joining.not_joined[id] =
            "its model (" + std::to_string(m.init.poses.size()) + " images) could not be adjusted: " + e.what();
      PGBA_LOG_WARN << "a model of " << m.init.poses.size() << " images is dropped: " << e.what();
    }
    records.push_back(record);
  }
  r->more_models = std::move(adjusted);
  std::stable_sort(r->more_models.begin(), r->more_models.end(),
                   [](const ComponentModel& a, const ComponentModel& b) {
                     return a.model.images.size() > b.model.images.size();
                   });
  timer.Stop()["models"] = records;
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
  const bool ran_initialisation = !r.initial.init.success;
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
    std::vector<GlobalInitResult> models = AverageMotions(tracks(), r.initial.pairs, triplets, o.global_init,
                                                          o.rotation_outliers, report, &r.initial.outliers_injected);
    SplitModels(tracks(), std::move(models), report, &r.initial.init, &r.more_models);
  } else if (CamerasChanged(input, r.initial.cameras)) {
    recalibrated = TracksWithCameras(input, r.initial.cameras);
  }
  if (options_.skip_refinement) return r;

  // 5. Relative motions and their local Hessians.
  if (r.hessians.motions.empty()) r.hessians = ComputeMotionHessians(tracks(), r.initial.init, options_.refinement, report);
  WriteHessiansToWorkspace(tracks(), options_, r.hessians, report);
  // 6. GCPs: the initial solution in their frame.
  const std::optional<GcpInput> gcps = TransferToGcpFrame(tracks(), options_, report, &r.initial.init);
  // 7. Pointless global BA, re-linearised at its solution until converged; 8. every registered
  //    image verified, a failing one registered again or dropped; 9. points triangulated with
  //    the final poses. For every model (the others with their own step 5).
  AdjustModels(tracks(), r.initial.pairs, options_, gcps ? &*gcps : nullptr, report, &r);
  // 10. Images left out joined by absolute pose against the models' points, models merged
  //     where they share points; the models that changed adjusted again (steps 5, 7-9) from
  //     their adjusted poses, with their joined images.
  if (ran_initialisation) {
    // A joined image passes the verification every registered image passes; the points with
    // the cameras of the adjustment (self-calibration's where it ran).
    ComponentJoiningOptions joining_options = options_.components;
    joining_options.registration.verification = options_.verification;
    std::vector<GlobalInitResult> models =
        JoinModels(r.refined.cameras.empty() ? tracks() : TracksWithCameras(tracks(), r.refined.cameras),
                   r.initial.pairs, joining_options, r, report, &r.joining);
    if (!models.empty()) {
      // An adjustment that fails with the joined images leaves the first one standing.
      const PointlessMapperResult first = r;
      const nlohmann::json stages = (*report)["stages"];
      try {
        KeepFirstAdjustmentStages(report);
        r.initial.init = std::move(models.front());
        r.more_models.clear();
        for (size_t m = 1; m < models.size(); ++m) r.more_models.push_back({std::move(models[m]), {}, {}, {}, {}});
        r.hessians = ComputeMotionHessians(tracks(), r.initial.init, options_.refinement, report);
        WriteHessiansToWorkspace(tracks(), options_, r.hessians, report);
        AdjustModels(tracks(), r.initial.pairs, options_, gcps ? &*gcps : nullptr, report, &r);
      } catch (const InputError& e) {
        PGBA_LOG_WARN << "the adjustment with the joined images failed, the first one is kept: " << e.what();
        ForgetWorkspaceHessians(options_);
        ComponentJoiningResult joining = std::move(r.joining);
        r = first;
        (*report)["stages"] = stages;
        (*report)["stages"]["components"]["adjustment_failed"] = e.what();
        // The images that joined are in no model again.
        for (const auto& [id, registration] : joining.joined)
          joining.not_joined[id] = std::string("joined, but the adjustment with it failed: ") + e.what();
        joining.joined.clear();
        joining.merges.clear();
        r.joining = std::move(joining);
      }
    }
  }
  RecordImages(tracks(), r, report);
  return r;
}

std::vector<const Reconstruction*> PointlessMapperResult::Models() const {
  std::vector<const Reconstruction*> models = {&model};
  for (const ComponentModel& m : more_models) models.push_back(&m.model);
  return models;
}

std::vector<const ImageVerificationResult*> PointlessMapperResult::Verifications() const {
  std::vector<const ImageVerificationResult*> verifications = {&verification};
  for (const ComponentModel& m : more_models) verifications.push_back(&m.verification);
  return verifications;
}

bool PointlessMapperResult::Placed(uint32_t image_id) const {
  if (refined.poses.count(image_id)) return true;
  return std::any_of(more_models.begin(), more_models.end(),
                     [&](const ComponentModel& m) { return m.refined.poses.count(image_id) > 0; });
}

GlobalMapperResult RunGlobalMapper(const Reconstruction& tracks, const GlobalMapperOptions& options, Report* report,
                                   const std::vector<TwoViewGeometry>* front_end) {
  PointlessMapperOptions initial_only;
  initial_only.mapper = options;
  initial_only.skip_refinement = true;
  return PointlessMapper(initial_only).Solve(tracks, report, {}, front_end).initial;
}

}  // namespace pgba
