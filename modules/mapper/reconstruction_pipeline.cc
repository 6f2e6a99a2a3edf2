#include "mapper/reconstruction_pipeline.h"

#include <filesystem>
#include <optional>

#include "evaluation/sigma.h"
#include "local_hessian/local_hessian_io.h"
#include "pgba/io/colmap_text.h"
#include "pgba/io/workspace.h"
#include "pgba/util/error.h"
#include "pgba/io/ply.h"
#include "pgba/scene/triangulate_model.h"
#include "pgba/util/logging.h"

namespace pgba {

void AddReconstructionSections(ConfigSchema* schema) {
  AddGlobalMapperSections(schema);
  AddRefinementSections(schema);
  schema->Add("gcp", GcpOptions{});
  schema->Add("convergence", ConvergenceOptions{});
}

void ReadReconstructionOptions(const Config& config, ReconstructionOptions* options) {
  ReadGlobalMapperOptions(config, &options->mapper);
  ReadRefinementOptions(config, &options->refinement);
  ReadSection(config, "gcp", &options->gcp);
  ReadSection(config, "convergence", &options->convergence);
  const std::string problem = options->convergence.Check();
  if (!problem.empty()) ThrowInputError(config.origin(), 0, "convergence." + problem);
}

namespace {

// With a GCP file: the initial solution moved into the GCP frame (stage "gcp_alignment").
std::optional<GcpInput> TransferToGcpFrame(const Reconstruction& tracks, const ReconstructionOptions& options,
                                           Report* report, GlobalInitResult* init) {
  if (options.gcp_path.empty()) return std::nullopt;
  StageTimer timer(report, "gcp_alignment");
  GcpInput gcps = LoadGcps(options.gcp_path, tracks, options.gcp);
  const GcpAlignment a = AlignToGcps(gcps, &init->poses, &init->triplets);
  nlohmann::json& stage = timer.Stop();
  stage["file"] = options.gcp_path;
  stage["gcps"] = gcps.gcps.size();
  stage["gcps_triangulated"] = a.num_gcps_used;
  stage["scale"] = a.transform.s;
  stage["rms_m"] = a.rms_before;
  return gcps;
}

// The GCPs triangulated with the final poses vs their coordinates (stage "gcp_check").
void CheckFinalGcps(const GcpInput& gcps, const std::map<uint32_t, Pose>& poses, Report* report) {
  StageTimer timer(report, "gcp_check");
  const GcpCheck check = CheckGcps(gcps, poses);
  timer.Stop().update(check.ToJson());
  PGBA_LOG_INFO << "GCPs with the final poses: " << check.num_gcps << " triangulated, RMS " << check.rms << " m, max "
                << check.max << " m";
}

// The stages after the initialisation: local hessians (unless given), pointless global BA,
// convergence curve, triangulation.
void Refine(const Reconstruction& tracks, const ReconstructionOptions& options, Report* report, bool record_convergence,
            bool hessians_given, ReconstructionOutput* out) {
  if (!hessians_given) {
    StageTimer timer(report, "local_hessians");
    out->hessians = PrepareLocalHessians(tracks, out->init.init.poses, out->init.init.triplets, options.refinement);
    nlohmann::json& stage = timer.Stop();
    stage["triplets"] = out->init.init.triplets.size();
    stage["motions"] = out->hessians.motions.size();
    stage["ok"] = out->hessians.result.num_ok();
    stage["rejected"] = LocalHessianStatusCounts(out->hessians.result);
    stage["rejected"].erase(LocalHessianStatusName(LocalHessianStatus::kOk));
    stage["triplet_rotation_misfit"] = out->hessians.triplet_rotation_misfit;
    stage["triplet_start"] = out->hessians.triplet_start;
  }
  const std::optional<GcpInput> gcps = TransferToGcpFrame(tracks, options, report, &out->init.init);
  {
    StageTimer timer(report, "global_ba");
    out->refined = RefinePoses(RefinementMethod::kPointless, tracks, out->init.init.poses, out->init.init.triplets,
                               &out->hessians, options.refinement, record_convergence, gcps ? &*gcps : nullptr);
    nlohmann::json& stage = timer.Stop();
    stage["params"] = out->refined.num_params;
    stage["iterations"] = out->refined.iterations;
    stage["adjust_seconds"] = out->refined.adjust_seconds;
    stage.update(out->refined.details);
    stage.erase("local_hessians");
  }
  if (gcps) CheckFinalGcps(*gcps, out->refined.poses, report);
  if (record_convergence) {
    StageTimer timer(report, "convergence");
    out->convergence = EvaluateConvergence(tracks, out->refined.history, options.convergence);
    out->refined.history.clear();
    timer.Stop().update(out->convergence.ToJson());
  }
  if (!out->refined.cameras.empty()) {
    (*report)["intrinsics"] = out->refined.intrinsics;
    for (const nlohmann::json& camera : out->refined.intrinsics)
      for (const nlohmann::json& p : camera["params"])
        PGBA_LOG_INFO << "camera " << camera["camera_id"] << " parameter " << p["index"] << ": " << p["initial"]
                      << " -> " << p["final"] << " (stddev " << p["stddev"] << ")";
  }
  {
    StageTimer timer(report, "triangulation");
    if (out->refined.cameras.empty()) {
      out->model = TriangulateModel(tracks, out->refined.poses);
    } else {  // with the estimated intrinsics (sparse/cameras.txt holds them)
      Reconstruction calibrated = tracks;
      calibrated.cameras = out->refined.cameras;
      out->model = TriangulateModel(calibrated, out->refined.poses);
    }
    timer.Stop()["points"] = out->model.points3D.size();
  }
  std::vector<std::string> dropped = out->init.init.images_dropped;
  for (uint32_t id : out->refined.excluded_images) {
    dropped.push_back(tracks.images.at(id).name);
    PGBA_LOG_WARN << "image dropped (in no usable triplet of the global BA): " << tracks.images.at(id).name;
  }
  (*report)["images_input"] = tracks.images.size();
  (*report)["images_registered"] = out->refined.poses.size();
  (*report)["images_dropped"] = dropped;
  (*report)["params"] = out->refined.num_params;
}

}  // namespace

ReconstructionOutput Reconstruct(const Reconstruction& tracks, const ReconstructionOptions& options, Report* report,
                                 bool record_convergence, const std::vector<TwoViewGeometry>* front_end) {
  ReconstructionOutput out;
  GlobalMapperOptions mapper = options.mapper;
  // Self-calibration reaches back to the triplet BA: a calibration that is only a prior bends
  // the relative motions the averaging starts from (TripletOptions::refine_intrinsics).
  if (!SelectRefinedIntrinsics(tracks, options.refinement).empty()) mapper.triplets.refine_intrinsics = true;
  out.init = RunGlobalMapper(tracks, mapper, report, front_end);
  if (CamerasChanged(tracks, out.init.cameras)) {  // focals from the view graph
    Refine(TracksWithCameras(tracks, out.init.cameras), options, report, record_convergence, /*hessians_given=*/false,
           &out);
  } else {
    Refine(tracks, options, report, record_convergence, /*hessians_given=*/false, &out);
  }
  return out;
}

ReconstructionOutput ReconstructFromWorkspace(const Reconstruction& tracks, const std::string& workspace,
                                             const ReconstructionOptions& options, Report* report) {
  namespace fs = std::filesystem;
  const fs::path ws(workspace);
  auto require = [&](const fs::path& p) {
    if (!fs::exists(p)) throw InputError(p.string() + ": missing (run `pgba init` or `pgba reconstruct` first)");
  };
  ReconstructionOutput out;
  {
    StageTimer timer(report, "workspace");
    require(WorkspacePairsPath(ws));
    require(WorkspaceTripletsPath(ws));
    require(ws / "init" / "images.txt");
    out.init.pairs = ReadPairs(WorkspacePairsPath(ws), tracks);
    out.init.init.triplets = ReadTriplets(WorkspaceTripletsPath(ws), tracks);
    const Reconstruction init = ReadColmapText((ws / "init").string(), /*points_optional=*/true);
    out.init.init.poses = MatchImagesByName(init, tracks).poses;
    // The cameras the mapper ended with (focals from the view graph) are init/'s.
    out.init.cameras = tracks.cameras;
    bool same_ids = init.cameras.size() == tracks.cameras.size();
    for (const auto& [id, cam] : tracks.cameras) same_ids = same_ids && init.cameras.count(id);
    if (same_ids) out.init.cameras = init.cameras;
    out.init.init.success = true;
    for (const auto& [id, im] : tracks.images)
      if (!out.init.init.poses.count(id)) out.init.init.images_dropped.push_back(im.name);
    if (out.init.init.poses.empty())
      throw InputError((ws / "init").string() + ": no image of the tracks model (another model's workspace?)");
    nlohmann::json& stage = timer.Stop();
    stage["triplets"] = out.init.init.triplets.size();
    stage["initial_poses"] = out.init.init.poses.size();
  }
  const fs::path hessians = WorkspaceLocalHessiansPath(ws);
  const bool given = fs::exists(hessians);
  if (given) {
    StageTimer timer(report, "local_hessians");
    // The motions again (without their local BAs: the file holds each model's own x0).
    out.hessians.motions =
        ChooseLocalMotions(tracks, out.init.init.poses, out.init.init.triplets, options.refinement.local_motions);
    out.hessians.result = ReadLocalHessians(hessians, tracks, out.hessians.motions);
    if (options.refinement.local_motions.kind == MotionKind::kWholeTracks &&
        options.refinement.local_motions.triplet_start_misfit > 0)
      MeasureTripletStart(tracks, out.init.init.poses, out.init.init.triplets, options.refinement.local_motions,
                          &out.hessians);
    nlohmann::json& stage = timer.Stop();
    stage["read_from"] = hessians.string();
    stage["ok"] = out.hessians.result.num_ok();
  }
  if (CamerasChanged(tracks, out.init.cameras)) {
    Refine(TracksWithCameras(tracks, out.init.cameras), options, report, /*record_convergence=*/false, given, &out);
  } else {
    Refine(tracks, options, report, /*record_convergence=*/false, given, &out);
  }
  return out;
}

void WriteReconstruction(const std::string& out, const Reconstruction& tracks, const ReconstructionOutput& result) {
  namespace fs = std::filesystem;
  WriteGlobalMapperWorkspace(out, tracks, result.init);
  WriteLocalHessians(WorkspaceLocalHessiansPath(out), tracks, result.hessians.result);
  WriteColmapText(result.model, (fs::path(out) / "sparse").string());
  WritePly(result.model, (fs::path(out) / "points.ply").string());
}

}  // namespace pgba
