// pgba init --tracks INPUT --out WS [--config F] [--rotation-outliers F]
// pgba init --database DB.db --out WS ...   (tracks from a COLMAP database's verified matches)
//
// Global initialisation from tracks (a COLMAP text model whose poses and point coordinates
// are ignored): verified pairs, triplets, rotation and translation averaging, per-triplet
// similarities. Writes WS/pairs.json, WS/triplets.json, WS/init/ and WS/report.json.
#include <filesystem>
#include <memory>
#include <string>

#include "apps/commands.h"
#include "apps/output_dir.h"
#include "mapper/mapper_workspace.h"
#include "mapper/pointless_mapper.h"
#include "mapper/run_pipeline.h"
#include "pgba/io/colmap_database.h"
#include "pgba/io/colmap_text.h"
#include "pgba/util/error.h"
#include "pgba/util/logging.h"

namespace pgba::app {

void RegisterInit(CLI::App& app) {
  struct Args {
    std::string tracks, database, out, config;
    double rotation_outliers = 0.0;
  };
  auto args = std::make_shared<Args>();
  CLI::App* sub = app.add_subcommand("init", "Global initialisation from tracks: pairs, triplets, averaging");
  CLI::Option* tracks =
      sub->add_option("--tracks", args->tracks, "COLMAP text model holding the observations and tracks");
  CLI::Option* database = sub->add_option(
      "--database", args->database, "COLMAP database.db: tracks from its verified matches (instead of --tracks)");
  tracks->excludes(database);
  database->excludes(tracks);
  sub->add_option("--out", args->out, "Workspace directory")->required();
  sub->add_option("--config", args->config, "JSON config or a preset of configs/ (init uses its sections pairs, triplets, global_init)");
  sub->add_option("--rotation-outliers", args->rotation_outliers,
                  "Fraction of relative rotations replaced by random ones before averaging (sensitivity test)")
      ->check(CLI::Range(0.0, 1.0));

  AddCommand(app, sub, [args] {
    if (args->tracks.empty() == args->database.empty())
      ThrowInputError("--tracks", 0, "give one of --tracks MODEL_DIR or --database DB.db");
    CheckOutputDir(args->out, kInitOutputs,
                   {{"--tracks", args->tracks}, {"--database", args->database}, {"--config", args->config}});
    // First: a re-run refused at its options or inputs must not leave the earlier result.
    RemovePreviousResults(args->out);
    // The one loader of every command: a configs/ preset with sections of other stages
    // (matching, local_hessian, ...) serves init too; only the mapper's sections are used.
    GlobalMapperOptions options = LoadRunOptions(args->config).reconstruction.mapper;
    if (args->rotation_outliers > 0) options.rotation_outliers.fraction = args->rotation_outliers;
    const Reconstruction tracks = args->database.empty()
                                      ? ReadColmapText(args->tracks)
                                      : TracksFromColmapDatabase(ReadColmapDatabase(args->database),
                                                                 TrackBuilderOptions{}, nullptr, args->database);
    const std::string source =
        args->database.empty() ? (std::filesystem::path(args->tracks) / "images.txt").string() : args->database;
    RequireEnoughImages(tracks, source);
    PrepareOutputDir(args->out);
    Report report;
    report["command"] = "init";
    if (args->database.empty())
      report["tracks"] = args->tracks;
    else
      report["database"] = args->database;
    try {
      const GlobalMapperResult result =
          NamingTheSource(source, [&] { return RunGlobalMapper(tracks, options, &report); });
      WriteGlobalMapperWorkspace(args->out, tracks, result);
      PointlessMapperOptions fingerprinted;
      fingerprinted.mapper = options;
      WriteWorkspaceFingerprint(args->out, FingerprintOf(tracks, fingerprinted, /*with_hessians=*/false));
      report["status"] = "ok";
      report.Write((std::filesystem::path(args->out) / "report.json").string());
    } catch (const std::exception& e) {
      // A failed init (or a full disk) leaves no fingerprint: its workspace is refused.
      RecordFailure(args->out, e, &report);
      throw;
    }
    PGBA_LOG_INFO << "wrote " << args->out << "/{pairs.json, triplets.json, init/, report.json}";
    return 0;
  });
}

}  // namespace pgba::app
