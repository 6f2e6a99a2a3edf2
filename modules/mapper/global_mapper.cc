#include "mapper/global_mapper.h"

#include <filesystem>

#include "pgba/io/colmap_text.h"
#include "pgba/io/workspace.h"
#include "pgba/scene/triangulate_model.h"
#include "pgba/util/error.h"
#include "pgba/util/logging.h"
#include "triplets/triplets.h"

namespace pgba {

void AddGlobalMapperSections(ConfigSchema* schema) {
  const GlobalMapperOptions defaults;
  schema->Add("pairs", defaults.pairs).Add("triplets", defaults.triplets).Add("global_init", defaults.global_init);
}

void ReadGlobalMapperOptions(const Config& config, GlobalMapperOptions* options) {
  ReadSection(config, "pairs", &options->pairs);
  ReadSection(config, "triplets", &options->triplets);
  ReadSection(config, "global_init", &options->global_init);
}

GlobalMapperResult RunGlobalMapper(const Reconstruction& tracks, const GlobalMapperOptions& options, Report* report) {
  GlobalMapperResult result;
  if (tracks.images.size() < 3) throw InputError("tracks: at least 3 images are needed, got " +
                                                 std::to_string(tracks.images.size()));
  {
    StageTimer timer(report, "pairs");
    PairStats stats;
    result.pairs = EstimatePairs(tracks, options.pairs, &stats);
    timer.Stop().update(ToJson(stats));
    PGBA_LOG_INFO << "pairs: " << result.pairs.size() << " verified of " << stats.pairs_estimated << " estimated";
  }
  if (result.pairs.empty()) throw InputError("tracks: no image pair could be verified (too few shared tracks?)");

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
  WriteColmapText(TriangulateModel(tracks, result.init.poses), (std::filesystem::path(workspace) / "init").string());
}

}  // namespace pgba
