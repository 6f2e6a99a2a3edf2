// pgba reconstruct --tracks INPUT --out OUT [--config F] [--workspace WS] [--gcp GCP_FILE]
//
// From tracks (a COLMAP text model whose poses and points are ignored) to the final poses:
// PointlessMapper::Solve (global initialisation, relative motions and their local Hessians,
// pointless global BA). Writes OUT/sparse/N/ (one COLMAP text model per component, largest
// first, each with its points.ply), the largest as OUT/sparse/ and OUT/points.ply,
// OUT/report.json and the workspace files (OUT/pairs.json, OUT/triplets.json, OUT/init/,
// OUT/motions.json, OUT/local_hessians.json). With --workspace WS the initialisation (and the
// motions with their local Hessians, if stored) are read from WS instead. With --gcp, the
// result is in the GCP frame (the GCP file format: src/pgba/io/gcp_file.h).
#include <filesystem>
#include <memory>
#include <string>

#include "apps/commands.h"
#include "apps/output_dir.h"
#include "local_hessian/local_hessian_io.h"
#include "mapper/dropped_images.h"
#include "mapper/mapper_workspace.h"
#include "mapper/run_pipeline.h"
#include "pgba/io/colmap_text.h"
#include "pgba/io/gcp_file.h"
#include "pgba/io/workspace_fingerprint.h"
#include "pgba/util/error.h"
#include "pgba/util/logging.h"

namespace pgba::app {

void RegisterReconstruct(CLI::App& app) {
  struct Args {
    std::string tracks, out, config, gcp, workspace;
  };
  auto args = std::make_shared<Args>();
  CLI::App* sub =
      app.add_subcommand("reconstruct", "Tracks -> initial poses -> local hessians -> pointless global BA");
  sub->add_option("--tracks", args->tracks, "COLMAP text model holding the observations and tracks")->required();
  sub->add_option("--out", args->out, "Output directory")->required();
  sub->add_option("--config", args->config, "JSON config (sections of init plus local_hessian, global_ba)");
  sub->add_option("--workspace", args->workspace,
                  "Continue from this workspace of `init` or `reconstruct` (its triplets, initial poses and, "
                  "where present, motions.json and local_hessians.json) instead of re-running the initialisation");
  sub->add_option("--gcp", args->gcp, "Ground control points (GCP/OBS lines): the result is put in their frame");

  AddCommand(app, sub, [args] {
    namespace fs = std::filesystem;
    CheckOutputDir(args->out, kReconstructOutputs,
                   {{"--tracks", args->tracks},
                    {"--config", args->config},
                    {"--gcp", args->gcp},
                    {"--workspace", args->workspace}});
    // First: a re-run refused at its options or inputs must not leave the earlier result.
    RemovePreviousResults(args->out);
    PointlessMapperOptions options = LoadRunOptions(args->config).reconstruction;
    options.gcp_path = args->gcp;
    options.workspace = args->out;
    if (!args->gcp.empty()) ReadGcpFile(args->gcp);  // a malformed file fails before any work
    Report report;
    report["command"] = "reconstruct";
    report["tracks"] = args->tracks;
    StageTimer input(&report, "input");  // the tracks model, resident until the end
    const Reconstruction tracks = ReadColmapText(args->tracks);
    input.Stop()["observations"] = tracks.NumObservations();
    const std::string source = (fs::path(args->tracks) / "images.txt").string();
    RequireEnoughImages(tracks, source);
    if (!args->workspace.empty())
      CheckWorkspaceFingerprint(args->workspace,
                                FingerprintOf(tracks, options, fs::exists(WorkspaceLocalHessiansPath(args->workspace))));
    PrepareOutputDir(args->out);
    const std::string report_path = (fs::path(args->out) / "report.json").string();
    try {
      const PointlessMapper mapper(options);
      const PointlessMapperResult result = NamingTheSource(source, [&] {
        return mapper.Solve(tracks, &report,
                            args->workspace.empty() ? PointlessMapperResult()
                                                    : ReadMapperWorkspace(tracks, args->workspace, options, &report));
      });
      StageTimer output(&report, "output");
      WriteReconstruction(args->out, tracks, result);
      WriteWorkspaceFingerprint(args->out, FingerprintOf(tracks, options, /*with_hessians=*/true));
      output.Stop();
      report["status"] = "ok";
      report.Write(report_path);
      if (const std::string dropped = DroppedImagesSummary(DroppedImages(tracks, result), tracks.images.size());
          !dropped.empty())
        PGBA_LOG_WARN << dropped;
      const size_t num_models = result.Models().size();
      PGBA_LOG_INFO << "wrote " << args->out << "/{sparse/, points.ply, report.json}: "
                    << report["images_registered"].get<size_t>() << " of " << tracks.images.size() << " images"
                    << (num_models == 1 ? ", " : " in " + std::to_string(num_models) + " models, ")
                    << result.model.points3D.size() << (num_models == 1 ? " points" : " points in the largest");
    } catch (const std::exception& e) {
      RecordFailure(args->out, e, &report);
      throw;
    }
    return 0;
  });
}

}  // namespace pgba::app
