#include "mapper/reconstruction_pipeline.h"

#include <filesystem>
#include <optional>

#include "evaluation/sigma.h"
#include "pgba/io/colmap_text.h"
#include "pgba/io/ply.h"
#include "pgba/scene/triangulate_model.h"
#include "pgba/util/logging.h"

namespace pgba {

void AddReconstructionSections(ConfigSchema* schema) {
  AddGlobalMapperSections(schema);
  AddRefinementSections(schema);
  schema->Add("gcp", GcpOptions{});
}

void ReadReconstructionOptions(const Config& config, ReconstructionOptions* options) {
  ReadGlobalMapperOptions(config, &options->mapper);
  ReadRefinementOptions(config, &options->refinement);
  ReadSection(config, "gcp", &options->gcp);
}

ReconstructionOptions LoadReconstructionOptions(const std::string& path) {
  ReconstructionOptions options;
  if (path.empty()) return options;
  ConfigSchema schema;
  AddReconstructionSections(&schema);
  ReadReconstructionOptions(LoadConfig(path, schema), &options);
  return options;
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

}  // namespace

ReconstructionOutput Reconstruct(const Reconstruction& tracks, const ReconstructionOptions& options, Report* report,
                                 bool record_convergence) {
  ReconstructionOutput out;
  out.init = RunGlobalMapper(tracks, options.mapper, report);
  {
    StageTimer timer(report, "local_hessians");
    out.hessians = PrepareLocalHessians(tracks, out.init.init.triplets, options.refinement.local_hessian);
    nlohmann::json& stage = timer.Stop();
    stage["triplets"] = out.init.init.triplets.size();
    stage["ok"] = out.hessians.result.num_ok();
    for (int s = 1; s < kNumLocalHessianStatus; ++s)
      stage["rejected"][LocalHessianStatusName(static_cast<LocalHessianStatus>(s))] = out.hessians.result.status_counts[s];
  }
  const std::optional<GcpInput> gcps = TransferToGcpFrame(tracks, options, report, &out.init.init);
  {
    StageTimer timer(report, "global_ba");
    out.refined = RefinePoses(RefinementMethod::kPointless, tracks, out.init.init.poses, out.init.init.triplets,
                              &out.hessians, options.refinement, record_convergence, gcps ? &*gcps : nullptr);
    nlohmann::json& stage = timer.Stop();
    stage["params"] = out.refined.num_params;
    stage["iterations"] = out.refined.iterations;
    stage["adjust_seconds"] = out.refined.adjust_seconds;
    stage.update(out.refined.details);
    stage.erase("local_hessians");
  }
  if (gcps) CheckFinalGcps(*gcps, out.refined.poses, report);
  if (record_convergence) {
    StageTimer timer(report, "convergence");
    for (const auto& poses : out.refined.history) out.convergence.push_back(EvaluateSigma(tracks, poses).rms);
    out.refined.history.clear();
    timer.Stop()["iterations"] = out.convergence.size();
  }
  {
    StageTimer timer(report, "triangulation");
    out.model = TriangulateModel(tracks, out.refined.poses);
    timer.Stop()["points"] = out.model.points3D.size();
  }
  std::vector<std::string> dropped = out.init.init.images_dropped;
  for (uint32_t id : out.refined.excluded_images) {
    dropped.push_back(tracks.images.at(id).name);
    PGBA_LOG_WARN << "image dropped (in no usable triplet of the global BA): " << tracks.images.at(id).name;
  }
  (*report)["images_input"] = tracks.images.size();
  (*report)["images_registered"] = out.refined.poses.size();
  (*report)["images_dropped"] = dropped;
  (*report)["params"] = out.refined.num_params;
  return out;
}

void WriteReconstruction(const std::string& out, const Reconstruction& tracks, const ReconstructionOutput& result) {
  namespace fs = std::filesystem;
  WriteGlobalMapperWorkspace(out, tracks, result.init);
  WriteColmapText(result.model, (fs::path(out) / "sparse").string());
  WritePly(result.model, (fs::path(out) / "points.ply").string());
}

}  // namespace pgba
