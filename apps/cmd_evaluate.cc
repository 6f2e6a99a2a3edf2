// pgba evaluate MODEL --obs INPUT [--gt GT] [--loop loop_pairs.txt] [--json F]
//
// Judges a model by the shared metrics (modules/evaluation): the tracks of INPUT
// triangulated with MODEL's poses held fixed (sigma), pose errors against a ground-truth
// model, loop-closure error on withheld correspondences. Images are matched by name.
#include <filesystem>
#include <iostream>
#include <string>

#include "apps/commands.h"
#include "evaluation/evaluation.h"
#include "pgba/io/colmap_text.h"
#include "pgba/io/loop_pairs.h"
#include "pgba/util/atomic_file.h"
#include "pgba/util/error.h"
#include "pgba/util/logging.h"
#include "pgba/util/output_path.h"

namespace pgba::app {

void RegisterEvaluate(CLI::App& app) {
  struct Args {
    std::string model, obs, gt, loop, json;
    double inlier_px = SigmaOptions{}.inlier_px;
  };
  auto args = std::make_shared<Args>();
  CLI::App* sub = app.add_subcommand("evaluate", "Evaluate a model: sigma, ground-truth pose errors, loop closure");
  sub->add_option("MODEL", args->model, "Evaluated COLMAP text model (its poses are used)")->required();
  sub->add_option("--obs", args->obs, "COLMAP text model whose observations and tracks are triangulated")
      ->required();
  sub->add_option("--gt", args->gt, "Ground-truth COLMAP text model (points3D.txt optional)");
  sub->add_option("--loop", args->loop, "Withheld loop correspondences (name_i x_i y_i name_j x_j y_j)");
  sub->add_option("--json", args->json, "Write the metrics as JSON to this file");
  sub->add_option("--inlier-px", args->inlier_px, "Inlier threshold of sigma, pixels")
      ->check(PositiveNumber())
      ->capture_default_str();

  AddCommand(app, sub, [args, sub] {
    if (sub->count("--json")) RequireOutputPath(args->json, "--json");
    EvaluationOptions options;
    options.sigma.inlier_px = args->inlier_px;
    if (!args->json.empty()) {
      CheckOutputFileApartFromInputs(
          args->json, {{"MODEL", args->model}, {"--obs", args->obs}, {"--gt", args->gt}, {"--loop", args->loop}});
      CheckOutputFile(args->json);  // a bad --json found now, not after the evaluation
      // An earlier result there must not outlive a failed evaluation and read as this one's.
      std::error_code ec;
      if (std::filesystem::is_regular_file(std::filesystem::symlink_status(args->json, ec)))
        std::filesystem::remove(args->json, ec);
    }

    const Reconstruction model = ReadColmapText(args->model, /*points_optional=*/true);
    const Reconstruction obs = ReadColmapText(args->obs);
    Reconstruction gt;
    if (!args->gt.empty()) gt = ReadColmapText(args->gt, /*points_optional=*/true);

    std::vector<LoopCorrespondence> loops;
    if (!args->loop.empty()) loops = ReadLoopPairs(args->loop);

    const EvaluationMetrics metrics =
        Evaluate(model, obs, args->gt.empty() ? nullptr : &gt, args->loop.empty() ? nullptr : &loops, options);
    if (metrics.images_registered == 0)
      PGBA_LOG_WARN << "no image of " << args->obs << " is in " << args->model << " (images are matched by name)";
    // Loop pairs that name images the model does not hold would read as "n/a" without a cause.
    if (metrics.loop && metrics.loop->num_unregistered > 0)
      PGBA_LOG_WARN << args->loop << ": " << metrics.loop->num_unregistered << " of "
                    << metrics.loop->num_correspondences << " loop pairs name an image that is not in " << args->model
                    << " (images are matched by name); left out";
    // Errors "computed" over no image at all would read as a perfect score.
    if (metrics.ground_truth && metrics.ground_truth->num_common == 0)
      ThrowInputError(args->gt, 0, "no image in common with " + args->model + " (images are matched by name)");
    // The file first: a write the disk refuses ends in its one error line, not after a table.
    if (!args->json.empty()) WriteStringAtomically(args->json, metrics.ToJson().dump(2) + "\n");
    metrics.PrintTable(std::cout);
    return 0;
  });
}

}  // namespace pgba::app
