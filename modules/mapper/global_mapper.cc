#include "mapper/global_mapper.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <optional>

#include "pgba/io/colmap_text.h"
#include "pgba/io/workspace.h"
#include "pgba/scene/triangulate_model.h"
#include "pgba/util/error.h"
#include "pgba/util/logging.h"
#include "triplets/triplets.h"

namespace pgba {

void AddGlobalMapperSections(ConfigSchema* schema) {
  const GlobalMapperOptions defaults;
  schema->Add("pairs", defaults.pairs)
      .Add("calibration", defaults.calibration)
      .Add("triplets", defaults.triplets)
      .Add("global_init", defaults.global_init);
}

void ReadGlobalMapperOptions(const Config& config, GlobalMapperOptions* options) {
  ReadSection(config, "pairs", &options->pairs);
  const std::string pairs_problem = options->pairs.Check();
  if (!pairs_problem.empty()) ThrowInputError(config.origin(), 0, "pairs." + pairs_problem);
  ReadSection(config, "calibration", &options->calibration);
  const std::string problem = options->calibration.Check();
  if (!problem.empty()) ThrowInputError(config.origin(), 0, "calibration." + problem);
  ReadSection(config, "triplets", &options->triplets);
  if (const std::string t = options->triplets.Check(); !t.empty()) ThrowInputError(config.origin(), 0, "triplets." + t);
  ReadSection(config, "global_init", &options->global_init);
}

namespace {

// Step 1 (and 2b): the verified pairs of `tracks` with its cameras, from the front end's
// geometries where given.
std::vector<TwoViewGeometry> VerifyPairs(const Reconstruction& tracks, const PairOptions& options, Report* report,
                                         const char* stage, const std::vector<TwoViewGeometry>* front_end) {
  StageTimer timer(report, stage);
  PairStats stats;
  std::vector<TwoViewGeometry> pairs = EstimatePairs(tracks, options, &stats, front_end);
  timer.Stop().update(ToJson(stats));
  PGBA_LOG_INFO << stage << ": " << pairs.size() << " verified of " << stats.pairs_estimated << " estimated";
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
    std::snprintf(line, sizeof(line), "camera %u: focal %.1f px -> %.1f px (relative sd %.2g, %d pairs)", c.camera_id,
                  c.prior_focal, c.estimated_focal, c.relative_sd, c.pairs_used);
    if (c.applied) {
      PGBA_LOG_INFO << "focal from the view graph: " << line;
    } else {
      PGBA_LOG_WARN << "focal from the view graph not used, the prior is kept: " << line << ": " << c.reason;
    }
  }
}

}  // namespace

Reconstruction TracksWithCameras(const Reconstruction& tracks, const std::map<uint32_t, Camera>& cameras) {
  Reconstruction out = tracks;
  out.cameras = cameras;
  return out;
}

bool CamerasChanged(const Reconstruction& tracks, const std::map<uint32_t, Camera>& cameras) {
  if (cameras.size() != tracks.cameras.size()) return true;
  for (const auto& [id, cam] : tracks.cameras) {
    const auto it = cameras.find(id);
    if (it == cameras.end() || it->second.model != cam.model || it->second.params != cam.params) return true;
  }
  return false;
}

GlobalMapperResult RunGlobalMapper(const Reconstruction& input_tracks, const GlobalMapperOptions& options,
                                   Report* report, const std::vector<TwoViewGeometry>* front_end) {
  GlobalMapperResult result;
  if (input_tracks.images.size() < 3)
    throw InputError("tracks: at least 3 images are needed, got " + std::to_string(input_tracks.images.size()));
  result.cameras = input_tracks.cameras;
  result.pairs = VerifyPairs(input_tracks, options.pairs, report, "pairs", front_end);
  if (result.pairs.empty()) throw InputError("tracks: no image pair could be verified (too few shared tracks?)");

  EstimateFocals(input_tracks, options.calibration, report, &result);
  // With new focals the pairs' relative poses (and inliers) are estimated again, and every
  // later stage sees the new cameras. The front end verified with the old focals: its
  // geometries do not hold for the new bearings.
  std::optional<Reconstruction> recalibrated;
  if (CamerasChanged(input_tracks, result.cameras)) {
    recalibrated = TracksWithCameras(input_tracks, result.cameras);
    result.pairs = VerifyPairs(*recalibrated, options.pairs, report, "pairs_recalibrated", nullptr);
    if (result.pairs.empty())
      throw InputError("tracks: no image pair could be verified with the focals from the view graph");
  }
  const Reconstruction& tracks = recalibrated ? *recalibrated : input_tracks;

  std::vector<Triplet> triplets;
  {
    StageTimer timer(report, "triplets");
    TripletStats stats;
    triplets = BuildTriplets(tracks, result.pairs, options.triplets, &stats);
    timer.Stop().update(ToJson(stats));  // BuildTriplets logs its own summary line
  }
  if (triplets.empty()) throw InputError("tracks: no triplet survived estimation (see report.json for reasons)");

  {
    StageTimer timer(report, "global_init");
    result.init = RunGlobalInitialisation(tracks, result.pairs, triplets, options.global_init);
    timer.Stop().update(GlobalInitReport(result.init));
  }
  if (!result.init.success) throw InputError("tracks: global initialisation failed: " + result.init.message);
  (*report)["images_input"] = tracks.images.size();
  (*report)["images_registered"] = result.init.poses.size();
  (*report)["images_dropped"] = result.init.images_dropped;
  for (const auto& name : result.init.images_dropped) PGBA_LOG_WARN << "image dropped (not in the largest component): " << name;
  PGBA_LOG_INFO << "global init: " << result.init.poses.size() << " / " << tracks.images.size()
                << " images registered, " << result.init.triplets.size() << " triplets";
  return result;
}

void WriteGlobalMapperWorkspace(const std::string& workspace, const Reconstruction& tracks,
                                const GlobalMapperResult& result) {
  std::filesystem::create_directories(workspace);
  WritePairs(WorkspacePairsPath(workspace), tracks, result.pairs);
  WriteTriplets(WorkspaceTripletsPath(workspace), tracks, result.init.triplets);
  const std::string init = (std::filesystem::path(workspace) / "init").string();
  if (result.cameras.empty() || !CamerasChanged(tracks, result.cameras)) {
    WriteColmapText(TriangulateModel(tracks, result.init.poses), init);
  } else {
    WriteColmapText(TriangulateModel(TracksWithCameras(tracks, result.cameras), result.init.poses), init);
  }
}

}  // namespace pgba
