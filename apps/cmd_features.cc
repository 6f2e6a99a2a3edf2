// pgba features --images DIR [--calib cameras.txt] [--camera-map FILE] --out WS
//   [--max-features N] [--root-sift|--no-root-sift] [--max-image-size PX] [--sift-implementation auto|pgba|opencv]
//   [--no-cache]
#include <filesystem>

#include "apps/commands.h"
#include "apps/output_dir.h"
#include "apps/report_merge.h"
#include "features/extract_features.h"
#include "pgba/io/report.h"
#include "pgba/util/timer.h"

namespace pgba::app {

void RegisterFeatures(CLI::App& app) {
  struct Args {
    std::string images, out;
    CalibrationInput calib;
    FeatureExtractionOptions options;
  };
  auto args = std::make_shared<Args>();
  CLI::App* sub = app.add_subcommand("features", "SIFT features of a folder of images into the workspace");
  sub->add_option("--images", args->images, "folder of images")->required();
  AddCalibrationOptions(sub, &args->calib);
  sub->add_option("--out", args->out, "workspace directory")->required();
  sub->add_option("--max-features", args->options.sift.max_features, "max features per image")
      ->check(InConfigRange("features.sift.max_features"))
      ->capture_default_str();
  sub->add_flag("--root-sift,!--no-root-sift", args->options.sift.root_sift, "RootSIFT descriptors")
      ->capture_default_str();
  sub->add_option("--max-image-size", args->options.sift.max_image_size,
                  "downscale images whose larger side exceeds this (pixels; 0 = never)")
      ->check(InConfigRange("features.sift.max_image_size"))
      ->capture_default_str();
  sub->add_option("--sift-implementation", args->options.sift.implementation,
                  "SIFT implementation: pgba (own, parallel inside an image), opencv, or auto (pgba from 0.5 MP)")
      ->check(CLI::IsMember({"auto", "pgba", "opencv"}))
      ->capture_default_str();
  sub->add_flag("!--no-cache", args->options.use_cache, "recompute even where cached features exist");
  AddCommand(app, sub, [args] {
    CheckOutputDir(args->out, kFeaturesOutputs,
                   {{"--images", args->images},
                    {"--calib", args->calib.cameras_path},
                    {"--camera-map", args->calib.camera_map_path}});
    // The index is rewritten only by a successful run; the per-image cache files stay (keyed).
    ForgetStage(args->out, "features", {"features/images.json"});
    const CpuTimer cpu;
    const FeatureExtractionResult r = ExtractFeatures(args->images, args->calib, args->out, args->options);
    nlohmann::json record = FeatureExtractionRecord(r);
    record["seconds"] = r.seconds;
    record["cpu_seconds"] = cpu.Seconds();
    record["load_average"] = NumberOrNull(LoadAverage1Min());
    record["peak_rss_mb"] = PeakRssMb();
    record["options"] = args->options;
    MergeStageIntoReport((std::filesystem::path(args->out) / "report.json").string(), "features", record);
    return 0;
  });
}

}  // namespace pgba::app
