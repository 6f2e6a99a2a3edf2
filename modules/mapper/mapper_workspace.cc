#include "mapper/mapper_workspace.h"

#include <filesystem>

#include "evaluation/sigma.h"
#include "local_hessian/local_hessian_io.h"
#include "pgba/io/colmap_text.h"
#include "pgba/io/ply.h"
#include "pgba/io/workspace.h"
#include "pgba/scene/triangulate_model.h"
#include "pgba/util/error.h"

namespace pgba {

namespace fs = std::filesystem;

void WriteGlobalMapperWorkspace(const std::string& workspace, const Reconstruction& tracks,
                                const GlobalMapperResult& result) {
  fs::create_directories(workspace);
  WritePairs(WorkspacePairsPath(workspace), tracks, result.pairs);
  WriteTriplets(WorkspaceTripletsPath(workspace), tracks, result.init.triplets);
  const std::string init = (fs::path(workspace) / "init").string();
  if (result.cameras.empty() || !CamerasChanged(tracks, result.cameras)) {
    WriteColmapText(TriangulateModel(tracks, result.init.poses), init);
  } else {
    WriteColmapText(TriangulateModel(TracksWithCameras(tracks, result.cameras), result.init.poses), init);
  }
}

PointlessMapperResult ReadMapperWorkspace(const Reconstruction& tracks, const std::string& workspace,
                                          const PointlessMapperOptions& options, Report* report) {
  const fs::path ws(workspace);
  auto require = [&](const fs::path& p) {
    if (!fs::exists(p)) ThrowInputError(p.string(), 0, "missing (run `pgba init` or `pgba reconstruct` first)");
  };
  PointlessMapperResult out;
  GlobalMapperResult& initial = out.initial;
  {
    StageTimer timer(report, "workspace");
    require(WorkspacePairsPath(ws));
    require(WorkspaceTripletsPath(ws));
    require(ws / "init" / "images.txt");
    initial.pairs = ReadPairs(WorkspacePairsPath(ws), tracks);
    initial.init.triplets = ReadTriplets(WorkspaceTripletsPath(ws), tracks);
    const Reconstruction init = ReadColmapText((ws / "init").string(), /*points_optional=*/true);
    initial.init.poses = MatchImagesByName(init, tracks).poses;
    // The cameras the mapper ended with (focals from the view graph) are init/'s.
    initial.cameras = tracks.cameras;
    bool same_ids = init.cameras.size() == tracks.cameras.size();
    for (const auto& [id, cam] : tracks.cameras) same_ids = same_ids && init.cameras.count(id);
    if (same_ids) initial.cameras = init.cameras;
    initial.init.success = true;
    for (const auto& [id, im] : tracks.images)
      if (!initial.init.poses.count(id)) initial.init.images_dropped.push_back(im.name);
    if (initial.init.poses.empty())
      ThrowInputError((ws / "init").string(), 0, "no image of the tracks model (another model's workspace?)");
    nlohmann::json& stage = timer.Stop();
    stage["triplets"] = initial.init.triplets.size();
    stage["initial_poses"] = initial.init.poses.size();
  }
  const fs::path hessians = WorkspaceLocalHessiansPath(ws);
  if (fs::exists(hessians)) {
    StageTimer timer(report, "local_hessians");
    require(WorkspaceMotionsPath(ws));
    WorkspaceMotions motions = ReadMotions(WorkspaceMotionsPath(ws), tracks);
    out.hessians.motions = std::move(motions.motions);
    out.hessians.triplet_rotation_misfit = motions.triplet_rotation_misfit;
    out.hessians.linearization_poses = std::move(motions.linearization_poses);
    out.hessians.result = ReadLocalHessians(hessians, tracks, out.hessians.motions);
    nlohmann::json& stage = timer.Stop();
    stage["read_from"] = hessians.string();
    stage["motions"] = out.hessians.motions.size();
    stage["ok"] = out.hessians.result.num_ok();
  }
  return out;
}

void WriteLocalHessianWorkspace(const std::string& workspace, const Reconstruction& tracks,
                                const PreparedHessians& hessians) {
  fs::create_directories(workspace);
  WriteMotions(WorkspaceMotionsPath(workspace), tracks,
               {hessians.motions, hessians.triplet_rotation_misfit, hessians.linearization_poses});
  WriteLocalHessians(WorkspaceLocalHessiansPath(workspace), tracks, hessians.result);
}

void WriteReconstruction(const std::string& out, const Reconstruction& tracks, const PointlessMapperResult& result) {
  WriteGlobalMapperWorkspace(out, tracks, result.initial);
  if (!result.hessians.released) WriteLocalHessianWorkspace(out, tracks, result.hessians);
  const fs::path sparse = fs::path(out) / "sparse";
  WriteColmapText(result.model, sparse.string());
  WritePly(result.model, (fs::path(out) / "points.ply").string());
  const std::vector<const Reconstruction*> models = result.Models();
  for (size_t m = 0; m < models.size(); ++m) {
    const fs::path dir = sparse / std::to_string(m);
    WriteColmapText(*models[m], dir.string());
    WritePly(*models[m], (dir / "points.ply").string());
  }
}

}  // namespace pgba
