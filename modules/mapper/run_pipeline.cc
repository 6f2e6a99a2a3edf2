#include "mapper/run_pipeline.h"

#include <filesystem>
#include <optional>

#include "features/feature_file.h"
#include "features/feature_index.h"
#include "mapper/dropped_images.h"
#include "mapper/mapper_workspace.h"
#include "matching/front_end_geometries.h"
#include "modules/calibration/pixel_shift.h"
#include "pgba/io/colmap_text.h"
#include "pgba/scene/camera.h"
#include "pgba/util/atomic_file.h"
#include "pgba/util/checksum.h"
#include "pgba/util/cpu_time.h"
#include "pgba/util/error.h"
#include "pgba/util/input_file.h"
#include "pgba/util/logging.h"
#include "pgba/util/text_format.h"
#include "pgba/util/timer.h"

namespace pgba {
namespace fs = std::filesystem;

RunOptions LoadRunOptions(const std::string& path) {
  RunOptions options;
  if (path.empty()) return options;
  ConfigSchema schema;
  schema.Add("features", options.features).Add("matching", options.matching);
  AddPointlessMapperSections(&schema);
  const Config config = LoadConfig(path, schema);
  ReadSection(config, "features", &options.features);
  ReadSection(config, "matching", &options.matching);
  ReadPointlessMapperOptions(config, &options.reconstruction);
  return options;
}

namespace {

// What the tracks of a workspace were computed from: the matching options, every image's
// features (the checksum of its feature file, which holds the hash of the photo's bytes: two
// photos swapped under their names change it) and the cameras (the two-view verification
// works on their bearings, so a re-run with another calibration must match again). Equal
// keys let a re-run skip matching.
nlohmann::json TracksKey(const std::string& workspace, const FeatureExtractionResult& features,
                         const MatchingOptions& options) {
  nlohmann::json images = nlohmann::json::array();
  for (const IndexedImage& im : features.index.images)
    images.push_back({im.name, im.num_features, Hex64(FeatureFileChecksum(FeatureFilePath(workspace, im.name)))});
  nlohmann::json cameras = nlohmann::json::array();
  for (const auto& [id, cam] : features.index.cameras)
    cameras.push_back({id, CameraModelName(cam.model), cam.width, cam.height, cam.params});
  return {{"matching", options}, {"features", features.index.images.size()}, {"images", images},
          {"cameras", cameras}};
}

// A key that is not a regular file (a FIFO would block the read forever) is an InputError
// naming it; a malformed one only means that the tracks are recomputed.
bool CachedTracksValid(const fs::path& out, const nlohmann::json& key) {
  const fs::path key_path = out / "tracks" / "key.json";
  std::error_code ec;
  if (!fs::exists(key_path, ec) || !fs::exists(out / "tracks" / "points3D.txt", ec)) return false;
  const std::string text = ReadRegularFile(key_path.string());
  const nlohmann::json stored = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
  return !stored.is_discarded() && stored == key;
}

// The tracks come back through the workspace's cameras.txt, which does not hold
// Camera::has_prior_focal_length: the catalog's cameras (same ids, same images) do.
void WithCatalogCameras(const FeatureExtractionResult& features, Reconstruction* tracks) {
  bool same_ids = tracks->cameras.size() == features.index.cameras.size();
  for (const auto& [id, cam] : tracks->cameras) same_ids = same_ids && features.index.cameras.count(id);
  if (same_ids) tracks->cameras = features.index.cameras;
}

// The front end's verified geometries the view graph starts from; none for a workspace whose
// matching/ holds none.
using FrontEndGeometries = std::optional<std::vector<TwoViewGeometry>>;

// The tracks (into `tracks`) and their verified geometries, matched or from the workspace.
FrontEndGeometries MatchOrReuse(const FeatureExtractionResult& features, const fs::path& out,
                                const MatchingOptions& options, Report* report, Reconstruction* tracks,
                                const char* stage_name = "match") {
  const nlohmann::json key = TracksKey(out.string(), features, options);
  StageTimer timer(report, stage_name);
  FrontEndGeometries result;
  if (CachedTracksValid(out, key)) {
    *tracks = ReadColmapText((out / "tracks").string());
    WithCatalogCameras(features, tracks);
    // Written with the tracks (WriteMatchingResult), so they describe the same images.
    const std::string geometries = FrontEndGeometriesPath(out.string());
    if (fs::exists(geometries)) {
      result = ReadFrontEndGeometries(geometries, *tracks);
    } else {
      PGBA_LOG_WARN << geometries << ": missing, the view graph estimates every pair from the tracks";
    }
    nlohmann::json& stage = timer.Stop();
    stage["cached"] = true;
    stage["tracks"] = tracks->points3D.size();
    PGBA_LOG_INFO << "match: reusing " << (out / "tracks").string() << " (same features and options)";
    return result;
  }
  MatchingResult r = MatchImages(out.string(), options);
  WithCatalogCameras(features, &r.tracks);
  WriteMatchingResult(out.string(), r);
  WriteStringAtomically((out / "tracks" / "key.json").string(), key.dump() + "\n");
  nlohmann::json& stage = timer.Stop();
  stage.update(MatchingRecord(r));
  stage["cached"] = false;
  *tracks = std::move(r.tracks);
  // Read back as a re-run reads them (17 significant digits), so that a run from cached
  // tracks gives the same poses as the run that matched.
  return ReadFrontEndGeometries(FrontEndGeometriesPath(out.string()), *tracks);
}

// The stages recorded from position `first` on (a pass that is then run again) folded into one
// stage `name`: its seconds the pass's wall time, its record {"stages": the pass's stages}. The
// stage table then sums to the run's time, in the order the stages ran, and a second pass's
// stages (recorded under the same names) do not replace the first's.
void FoldStages(Report* report, size_t first, const std::string& name, double seconds, double cpu_seconds) {
  nlohmann::json& stages = (*report)["stages"];
  nlohmann::json folded = nlohmann::json::object();
  for (auto it = stages.begin(); it != stages.end();) {
    if (it.value().value("order", size_t{0}) >= first) {
      folded[it.key()] = it.value();
      it = stages.erase(it);
    } else {
      ++it;
    }
  }
  report->AddStage(name, seconds, cpu_seconds)["stages"] = folded;
}

size_t NumStages(const Report& report) { return report.json().value("stages", nlohmann::json::object()).size(); }

PointlessMapperResult ReconstructFromFrontEnd(const Reconstruction& tracks, const FrontEndGeometries& geometries,
                                              const PointlessMapper& mapper, Report* report) {
  return mapper.Solve(tracks, report, {}, geometries ? &*geometries : nullptr);
}

}  // namespace

RunOutput RunPipeline(const std::string& images_dir, const CalibrationInput& calibration, const std::string& out,
                      const RunOptions& options, Report* report) {
  RunOutput result;
  const fs::path ws(out);
  fs::create_directories(ws);
  FeatureExtractionResult features;
  {
    StageTimer timer(report, "features");
    features = ExtractFeatures(images_dir, calibration, out, options.features);
    timer.Stop().update(FeatureExtractionRecord(features));
  }
  if (features.index.images.size() < 3)
    ThrowInputError(images_dir, 0, std::to_string(features.index.images.size()) +
                     " usable image(s); a reconstruction needs at least 3 overlapping images");
  FrontEndGeometries geometries = MatchOrReuse(features, ws, options.matching, report, &result.tracks);
  if (result.tracks.points3D.empty())
    ThrowInputError(images_dir, 0, "no verified matches between the images (do they overlap?)");

  PointlessMapperOptions reconstruction = options.reconstruction;
  // Without a calibration file the cameras are priors (EXIF or the default focal), and a file
  // given with --calib-prior is one too: the default intrinsics.cameras "auto" then estimates them.
  reconstruction.refinement.calibration_is_prior =
      options.calibration_is_prior || features.calibration_source.rfind("file:", 0) != 0;
  reconstruction.record_convergence = true;
  reconstruction.workspace = out;
  (*report)["calibration_is_prior"] = reconstruction.refinement.calibration_is_prior;
  const PointlessMapper mapper(reconstruction);
  const size_t first_pass_stage = NumStages(*report);
  Timer first_pass_timer;
  CpuTimer first_pass_cpu;
  // A stage's finding about the tracks ("no image pair could be verified") names the photos.
  result.reconstruction =
      NamingTheSource(images_dir, [&] { return ReconstructFromFrontEnd(result.tracks, geometries, mapper, report); });
  const double first_pass_seconds = first_pass_timer.Seconds(), first_pass_cpu_seconds = first_pass_cpu.Seconds();

  // The tracks were verified with the cameras before self-calibration; when it moved them by
  // more than calibration.rematch_shift_px, match again with the refined cameras (written to
  // the workspace's feature index for the matcher, then the catalog's put back) and
  // reconstruct once more, from them. The report's stages then describe this second pass; the
  // first is one stage, "first_pass", with its own stages inside.
  const std::map<uint32_t, Camera>& refined = result.reconstruction.refined.cameras;
  const double rematch_px = options.reconstruction.mapper.calibration.rematch_shift_px;
  const double shift = refined.empty() ? 0.0 : MaxPixelShift(features.index.cameras, refined);
  if (rematch_px > 0 && shift > rematch_px) {
    FoldStages(report, first_pass_stage, "first_pass", first_pass_seconds, first_pass_cpu_seconds);
    PGBA_LOG_INFO << "self-calibration moved image points by up to " << FormatNumber("%.1f", shift)
                  << " px: matching again with the refined cameras, then a second pass";
    FeatureExtractionResult recalibrated = features;
    recalibrated.index.cameras = refined;
    for (auto& [id, cam] : recalibrated.index.cameras) cam.has_prior_focal_length = true;  // estimated now
    WriteFeatureIndex(out, recalibrated.index);
    // The second matching verifies with the refined cameras: its geometries hold for them.
    geometries = MatchOrReuse(recalibrated, ws, options.matching, report, &result.tracks, "match_recalibrated");
    WriteFeatureIndex(out, features.index);
    result.reconstruction =
        NamingTheSource(images_dir, [&] { return ReconstructFromFrontEnd(result.tracks, geometries, mapper, report); });
  }
  (*report)["rematch_shift_px"] = shift;
  // The values the run began from beside each estimated camera's (a second pass starts from
  // the first's result), and why each image left out was.
  if (report->json().contains("intrinsics") && report->json()["intrinsics"].is_array())
    for (nlohmann::json& camera : (*report)["intrinsics"]) {
      const auto prior = features.index.cameras.find(camera.value("camera_id", 0u));
      if (prior != features.index.cameras.end()) camera["prior_params"] = prior->second.params;
    }
  const std::vector<DroppedImage> dropped = DroppedImages(result.tracks, result.reconstruction);
  (*report)["images_dropped_reason"] = DroppedImagesJson(dropped);
  if (!dropped.empty()) PGBA_LOG_WARN << DroppedImagesSummary(dropped, result.tracks.images.size());
  StageTimer output(report, "output");
  WriteReconstruction(out, result.tracks, result.reconstruction);
  output.Stop();
  return result;
}

// The features section's options are checked by the extractor (modules/features).
std::string RunOptions::Check() const {
  if (const std::string p = matching.Check(); !p.empty()) return "matching." + p;
  return reconstruction.Check();
}

}  // namespace pgba
