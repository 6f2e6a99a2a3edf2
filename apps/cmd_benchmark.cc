// pgba benchmark --tracks INPUT --out OUT [--gt GT] [--loop loop_pairs.txt] [--config F]
//                [--rotation-outliers F] [--outlier-sweep] [--triplet-split]
//                [--perturb-deg D [--perturb-seed S]] [--start MODEL]
//
// The paper's evaluation: one shared initialisation, then pointless BA, point-based BA and
// Aver_BA from the same initial poses. Writes OUT/models/<method>/ (COLMAP text),
// OUT/benchmark.json, OUT/convergence.svg (paper Figure 3) and, with --outlier-sweep,
// OUT/outlier_sweep.svg (paper Figure 4); prints the paper's tables.
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <string>

#include "apps/commands.h"
#include "apps/output_dir.h"
#include "benchmark/benchmark.h"
#include "benchmark/perturbed_start.h"
#include "mapper/run_pipeline.h"
#include "pgba/io/colmap_text.h"
#include "pgba/io/loop_pairs.h"
#include "pgba/util/atomic_file.h"
#include "pgba/util/error.h"
#include "pgba/util/logging.h"

namespace pgba::app {

void RegisterBenchmark(CLI::App& app) {
  struct Args {
    std::string tracks, out, config, gt, loop, start;
    double rotation_outliers = 0.0;
    bool outlier_sweep = false;
    bool triplet_split = false;
    bool no_convergence = false;
    double perturb_deg = 0.0;
    uint64_t perturb_seed = 1;
  };
  auto args = std::make_shared<Args>();
  CLI::App* sub = app.add_subcommand("benchmark", "Pointless BA vs point-based BA vs Aver_BA on one initialisation");
  sub->add_option("--tracks", args->tracks, "COLMAP text model holding the observations and tracks")->required();
  sub->add_option("--out", args->out, "Output directory")->required();
  sub->add_option("--gt", args->gt, "Ground-truth COLMAP text model (points3D.txt optional)");
  sub->add_option("--loop", args->loop, "Withheld loop correspondences (name_i x_i y_i name_j x_j y_j)");
  sub->add_option("--config", args->config, "JSON config (sections of reconstruct)");
  sub->add_option("--rotation-outliers", args->rotation_outliers,
                  "Fraction of relative rotations replaced by random ones before averaging")
      ->check(CLI::Range(0.0, 1.0));
  sub->add_flag("--outlier-sweep", args->outlier_sweep,
                "Also run 0..22% relative-rotation outliers (pointless and Aver_BA; paper Figure 4)");
  sub->add_option("--perturb-deg", args->perturb_deg,
                  "Rotate every initial pose by this many degrees about a random axis (centres moved alike) before "
                  "the methods run: a start the defaults were not chosen on")
      ->check(CLI::Range(0.0, 30.0));
  sub->add_option("--perturb-seed", args->perturb_seed, "Seed of --perturb-deg's random axes");
  sub->add_option("--start", args->start,
                  "COLMAP text model whose poses (matched by image name) replace the initialisation's: every "
                  "method starts there (e.g. another method's result, to see whether it stays)");
  sub->add_flag("--no-convergence", args->no_convergence, "Skip the per-iteration sigma curves");
  sub->add_flag("--triplet-split", args->triplet_split,
                "Also run the point-based BA over the triplets' own tracks (the objective the pointless BA "
                "approximates)");

  AddCommand(app, sub, [args] {
    namespace fs = std::filesystem;
    CheckOutputDir(args->out, kBenchmarkOutputs,
                   {{"--tracks", args->tracks}, {"--gt", args->gt}, {"--loop", args->loop}, {"--config", args->config},
                    {"--start", args->start}});
    // First: a re-run refused at its options or inputs must not leave the earlier result.
    RemovePreviousResults(args->out, kBenchmarkResults);
    const PointlessMapperOptions ro = LoadRunOptions(args->config).reconstruction;
    BenchmarkOptions options;
    options.mapper = ro.mapper;
    options.refinement = ro.refinement;
    options.convergence = !args->no_convergence;
    options.triplet_split = args->triplet_split;
    if (args->rotation_outliers > 0) options.mapper.rotation_outliers.fraction = args->rotation_outliers;
    if (args->outlier_sweep)
      for (int k = 0; k <= 11; ++k) options.outlier_sweep.push_back(0.02 * k);

    const Reconstruction tracks = ReadColmapText(args->tracks);
    const std::string source = (fs::path(args->tracks) / "images.txt").string();
    RequireEnoughImages(tracks, source);
    Reconstruction gt;
    if (!args->gt.empty()) gt = ReadColmapText(args->gt, /*points_optional=*/true);
    std::vector<LoopCorrespondence> loops;
    if (!args->loop.empty()) loops = ReadLoopPairs(args->loop);
    Reconstruction start;
    if (!args->start.empty()) start = ReadColmapText(args->start, /*points_optional=*/true);

    PrepareOutputDir(args->out);
    Report report;
    GlobalMapperResult init = NamingTheSource(source, [&] { return RunGlobalMapper(tracks, options.mapper, &report); });
    if (!args->start.empty()) {
      std::map<std::string, const Image*> by_name;
      for (const auto& [id, image] : start.images) by_name[image.name] = &image;
      size_t replaced = 0;
      for (auto& [id, pose] : init.init.poses) {
        const auto it = by_name.find(tracks.images.at(id).name);
        if (it == by_name.end()) continue;
        pose = it->second->pose;
        ++replaced;
      }
      if (replaced == 0)
        throw InputError((std::filesystem::path(args->start) / "images.txt").string() +
                         ": no image of the initialisation is in this model (images are matched by name)");
      std::cout << "start: " << replaced << " of " << init.init.poses.size() << " initial poses from " << args->start
                << "\n";
    }
    if (args->perturb_deg > 0) init.init.poses = PerturbedStart(init.init.poses, args->perturb_deg, args->perturb_seed);
    // Every method runs with the cameras the mapper ends with (focals from the view graph).
    const Reconstruction calibrated = TracksWithCameras(tracks, init.cameras);
    const BenchmarkResult result = NamingTheSource(source, [&] {
      return RunBenchmark(calibrated, init, args->gt.empty() ? nullptr : &gt, args->loop.empty() ? nullptr : &loops,
                          options);
    });

    const fs::path out(args->out);
    try {
      for (const MethodOutcome& m : result.methods)
        WriteColmapText(m.model, (out / "models" / RefinementMethodName(m.method)).string());
      nlohmann::json j = result.ToJson();
      j["init"]["stages"] = report.json()["stages"];
      j["tracks"] = args->tracks;
      j["rotation_outliers"] = args->rotation_outliers;
      j["perturb_deg"] = args->perturb_deg;
      j["perturb_seed"] = args->perturb_seed;
      if (!args->start.empty()) j["start"] = args->start;
      WriteStringAtomically((out / "convergence.svg").string(), ConvergencePlot(result));
      if (!result.sweep.empty())
        WriteStringAtomically((out / "outlier_sweep.svg").string(), OutlierSweepPlot(result));
      WriteStringAtomically((out / "benchmark.json").string(), j.dump(2) + "\n");
    } catch (const std::exception&) {
      // A write the disk refused: no model or plot of this run is left to read as its result.
      try {
        RemovePreviousResults(args->out, kBenchmarkResults);
      } catch (const std::exception&) {
      }
      throw;
    }
    PrintBenchmarkTables(result, std::cout);
    std::cout << "\nwrote " << args->out << "/{benchmark.json, convergence.svg"
              << (result.sweep.empty() ? "" : ", outlier_sweep.svg") << ", models/}\n";
    return 0;
  });
}

}  // namespace pgba::app
