// pgba init --tracks INPUT --out WS [--config F] [--rotation-outliers F]
//
// Global initialisation from tracks (a COLMAP text model whose poses and point coordinates
// are ignored): verified pairs, triplets, rotation and translation averaging, per-triplet
// similarities. Writes WS/pairs.json, WS/triplets.json, WS/init/ and WS/report.json.
#include <filesystem>
#include <memory>
#include <string>

#include "apps/commands.h"
#include "mapper/global_mapper.h"
#include "pgba/io/colmap_text.h"
#include "pgba/util/logging.h"

namespace pgba::app {

void RegisterInit(CLI::App& app) {
  struct Args {
    std::string tracks, out, config;
    double rotation_outliers = 0.0;
  };
  auto args = std::make_shared<Args>();
  CLI::App* sub = app.add_subcommand("init", "Global initialisation from tracks: pairs, triplets, averaging");
  sub->add_option("--tracks", args->tracks, "COLMAP text model holding the observations and tracks")->required();
  sub->add_option("--out", args->out, "Workspace directory")->required();
  sub->add_option("--config", args->config, "JSON config (sections pairs, triplets, global_init)");
  sub->add_option("--rotation-outliers", args->rotation_outliers,
                  "Fraction of relative rotations replaced by random ones before averaging (sensitivity test)")
      ->check(CLI::Range(0.0, 1.0));

  AddCommand(app, sub, [args] {
    GlobalMapperOptions options;
    if (!args->config.empty()) {
      ConfigSchema schema;
      AddGlobalMapperSections(&schema);
      ReadGlobalMapperOptions(LoadConfig(args->config, schema), &options);
    }
    if (args->rotation_outliers > 0) options.global_init.outliers.fraction = args->rotation_outliers;
    const Reconstruction tracks = ReadColmapText(args->tracks);
    Report report;
    report["command"] = "init";
    report["tracks"] = args->tracks;
    const GlobalMapperResult result = RunGlobalMapper(tracks, options, &report);
    WriteGlobalMapperWorkspace(args->out, tracks, result);
    report.Write((std::filesystem::path(args->out) / "report.json").string());
    PGBA_LOG_INFO << "wrote " << args->out << "/{pairs.json, triplets.json, init/, report.json}";
    return 0;
  });
}

}  // namespace pgba::app
