// pgba synth --scenario S --out DIR [--seed N] [--noise PX] [--outliers F] [--images N]
//   [--k1 K] [--focal-prior-error E]
// Writes DIR/gt/ (true camera, poses and points, noisy observations), DIR/input/ (the prior
// camera, same observations and tracks; poses identity, points at the origin) and, for
// scenarios that withhold a loop, DIR/loop_pairs.txt.
//
// pgba synth --render --out DIR [--seed N] [--images N] [--width W] [--height H] [--focal F]
//   [--supersampling S] [--image-noise G] [--k1 K] [--focal-prior-error E]
// Renders photographs of a textured room from a ring of known poses (rendered_scene.h):
// DIR/images/*.png, DIR/cameras.txt (the prior), DIR/gt/ (true camera and poses), DIR/loop.txt.
//
// pgba synth --render --scene aerial --out DIR [--images N (1000)] [--width W (1024)]
//   [--height H (768)] [--strips S] [--forward-overlap F] [--side-overlap F] [--ground-sample M] ...
// Renders an aerial block (aerial_block.h): a textured town flown in strips; DIR/images/,
// DIR/cameras.txt, DIR/gt/, DIR/overlap.txt (pairs whose true footprints overlap).
//
// --k1: radial distortion of the true lens (SIMPLE_RADIAL); --focal-prior-error: relative
// error of the calibration handed to the pipeline, which has no distortion
// (modules/synthetic/synthetic_lens.h).
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>

#include "apps/commands.h"
#include "modules/synthetic/aerial_block.h"
#include "modules/synthetic/rendered_scene.h"
#include "modules/synthetic/synthetic_lens.h"
#include "modules/synthetic/synthetic_scene.h"
#include "pgba/io/colmap_text.h"
#include "pgba/io/loop_pairs.h"
#include "pgba/util/error.h"
#include "pgba/util/output_path.h"
#include "pgba/util/timer.h"

namespace pgba::app {

namespace {

struct SynthArgs {
  std::string scenario;
  std::string out;
  int64_t seed = 1;  // signed so that a negative seed is rejected rather than wrapped
  SyntheticOptions options;
  bool render = false;
  std::string scene = "room";  // --render: room | object | aerial
  RenderedSceneOptions render_options;
  AerialBlockOptions aerial = DefaultAerialBlockOptions();
};

int RunRenderAerial(const SynthArgs& args) {
  const AerialBlockOptions& options = args.aerial;
  const AerialBlock block = MakeAerialBlock(options);
  const double render_s = WriteAerialBlock(block, options, args.out);
  const Camera& cam = block.gt.cameras.at(1);
  const size_t n = block.gt.images.size();
  std::printf("synth --render aerial (seed %llu): %zu images %dx%d in %d strips, %s f %.1f px (prior %.1f px), "
              "altitude %.1f m, %zu quads, extent %.1f m; textures %.2f s, rendered and written in %.2f s "
              "(%.3f s per image)\n",
              static_cast<unsigned long long>(options.image.seed), n, cam.width, cam.height, block.strips,
              CameraModelName(cam.model), cam.params[0], block.calibration.params[0], block.altitude,
              block.quads.size(), block.extent, block.texture_seconds, render_s, render_s / n);
  std::printf("wrote %s/{images/, cameras.txt, gt/, overlap.txt}\n", args.out.c_str());
  return 0;
}

int RunRender(const SynthArgs& args) {
  RenderedSceneOptions options = args.render_options;
  options.seed = static_cast<uint64_t>(args.seed);
  const RenderedScene scene = args.scene == "object" ? RenderObjectScene(options) : RenderRoomScene(options);
  Timer timer;
  WriteRenderedScene(scene, args.out);
  const Camera& cam = scene.gt.cameras.at(1);
  std::printf("synth --render %s (seed %llu): %zu images %dx%d, %s f %.1f px (prior %.1f px), ring extent %.2f m, "
              "rendered in %.2f s, written in %.2f s\n",
              args.scene.c_str(), static_cast<unsigned long long>(options.seed), scene.images.size(), cam.width,
              cam.height, CameraModelName(cam.model), cam.params[0], scene.calibration.params[0], scene.extent,
              scene.seconds,
              timer.Seconds());
  std::printf("wrote %s/{images/, cameras.txt, gt/, loop.txt}\n", args.out.c_str());
  return 0;
}

int RunSynth(const SynthArgs& args) {
  SyntheticOptions options = args.options;
  if (!ParseSyntheticScenario(args.scenario, &options.scenario))
    ThrowInputError("--scenario", 0, "unknown scenario '" + args.scenario + "' (orbit, longfocal, aerial, planar)");
  Timer timer;
  const SyntheticScene scene = GenerateSyntheticScene(options);
  const double generate_s = timer.Seconds();

  namespace fs = std::filesystem;
  const fs::path out(args.out);
  fs::create_directories(out);
  WriteColmapText(scene.gt, (out / "gt").string());
  WriteColmapText(scene.input, (out / "input").string());
  const fs::path loop = out / "loop_pairs.txt";
  if (!scene.loop_pairs.empty()) {
    WriteLoopPairs(scene.loop_pairs, loop.string());
  } else {
    std::error_code ec;
    fs::remove(loop, ec);  // a stale file from another scenario would describe a loop that is not there
  }

  const size_t obs = scene.gt.NumObservations();
  const size_t points = scene.gt.points3D.size();
  std::printf(
      "synth %s (seed %llu, noise %.3g px, outliers %.3g): %zu images, %zu points, %zu observations, "
      "mean track length %.2f, %zu outliers, %zu loop pairs, extent %.1f m, %.2f s\n",
      SyntheticScenarioName(options.scenario), static_cast<unsigned long long>(options.seed), options.noise_px,
      options.outlier_fraction, scene.gt.images.size(), points, obs, points ? double(obs) / points : 0.0,
      scene.outliers.size(), scene.loop_pairs.size(), scene.extent, generate_s);
  const Camera& truth = scene.gt.cameras.begin()->second;
  const Camera& prior = scene.input.cameras.begin()->second;
  std::printf("camera: %s f %.1f px (input/: %s f %.1f px)\n", CameraModelName(truth.model), truth.MeanFocal(),
              CameraModelName(prior.model), prior.MeanFocal());
  std::printf("wrote %s/gt, %s/input%s\n", out.string().c_str(), out.string().c_str(),
              scene.loop_pairs.empty() ? "" : (", " + loop.string()).c_str());
  return 0;
}

// Every count option has an upper bound: 2e9 points ended in std::bad_alloc.
constexpr int kMaxImages = 20000;
constexpr int kMaxPoints = 5000000;
constexpr int kMaxStrips = 1000;
void RequireCountAtMost(const CLI::App* sub, const char* option, int value, int max) {
  if (sub->count(option) && value > max)
    ThrowInputError(option, 0, "must be <= " + std::to_string(max) + ", got " + std::to_string(value));
}

}  // namespace

void RegisterSynth(CLI::App& app) {
  auto args = std::make_shared<SynthArgs>();
  CLI::App* sub = app.add_subcommand("synth", "Generate a synthetic scene with ground truth");
  sub->add_option("--scenario", args->scenario, "orbit | longfocal | aerial | planar (tracks only; not with --render)");
  sub->add_flag("--render", args->render,
                "Render photographs with known poses instead of tracks (--scene room, object or aerial)");
  sub->add_option("--scene", args->scene,
                  "--render: room (a textured room seen from a ring, default) | object (a textured object in a plain room, "
                  "seen all around) | aerial (a textured town flown "
                  "in strips, 1000 images 1024x768 by default)");
  sub->add_option("--forward-overlap", args->aerial.forward_overlap,
                  "--scene aerial: overlap along a strip, [0.5, 0.9] (default 0.75)");
  sub->add_option("--side-overlap", args->aerial.side_overlap,
                  "--scene aerial: overlap between strips, [0.2, 0.8] (default 0.5)");
  sub->add_option("--ground-sample", args->aerial.ground_sample_m,
                  "--scene aerial: ground distance of a pixel at nadir, metres (default 0.1)");
  sub->add_option("--out", args->out, "Output directory (gt/, input/, loop_pairs.txt; with --render: images/, "
                                      "cameras.txt, gt/, loop.txt)")
      ->required();
  sub->add_option("--seed", args->seed, "Random seed, >= 0 (default 1)");
  sub->add_option("--noise", args->options.noise_px, "Gaussian observation noise, px per coordinate (default 0.5)");
  sub->add_option("--outliers", args->options.outlier_fraction,
                  "Fraction of observations replaced by random pixels, in [0, 1) (default 0)");
  sub->add_option("--images", args->options.num_images,
                  "Number of images, >= 3 (default: the scenario's; --render: 20)");
  sub->add_option("--points", args->options.num_points, "Number of scene points (default: the scenario's)");
  sub->add_option("--strips", args->options.num_strips,
                  "aerial (tracks or --render --scene aerial): number of strips (default: tracks 6, more for big "
                  "blocks; rendered: a square block)");
  sub->add_option("--width", args->render_options.width, "--render: image width, pixels (default 640)");
  sub->add_option("--height", args->render_options.height, "--render: image height, pixels (default 480)");
  sub->add_option("--focal", args->render_options.focal_px, "--render: focal length, pixels (default 0.8 x width)");
  sub->add_option("--supersampling", args->render_options.supersampling,
                  "--render: samples per pixel and axis, 1..4 (default 2)");
  sub->add_option("--image-noise", args->render_options.image_noise,
                  "--render: Gaussian pixel noise, grey levels (default 1.5)");
  sub->add_option("--k1", args->options.k1,
                  "Radial distortion k1 of the true lens, in [-1, 1] and invertible over the image (default 0: "
                  "pinhole); gt/ holds SIMPLE_RADIAL");
  sub->add_option("--focal-prior-error", args->options.focal_prior_error,
                  "Relative error of the focal of the calibration given to the pipeline (input/, or cameras.txt "
                  "with --render), in [-0.5, 1], distortion 0 (default 0)");
  AddCommand(app, sub, [args, sub] {
    SynthArgs a = *args;
    RequireOutputPath(a.out, "--out");
    RequireCountAtMost(sub, "--images", a.options.num_images, kMaxImages);
    RequireCountAtMost(sub, "--points", a.options.num_points, kMaxPoints);
    RequireCountAtMost(sub, "--strips", a.options.num_strips, kMaxStrips);
    if (a.seed < 0) ThrowInputError("--seed", 0, "must be >= 0, got " + std::to_string(a.seed));
    static const char* kTrackOnly[] = {"--scenario", "--noise", "--outliers", "--points"};
    static const char* kRenderOnly[] = {"--width", "--height", "--focal", "--supersampling", "--image-noise",
                                        "--scene"};
    static const char* kAerialOnly[] = {"--forward-overlap", "--side-overlap", "--ground-sample"};
    if (a.render) {
      for (const char* opt : kTrackOnly)
        if (sub->count(opt)) ThrowInputError(opt, 0, "does not apply to --render");
      if (a.scene == "aerial") {
        AerialBlockOptions& o = a.aerial;
        o.image.seed = static_cast<uint64_t>(a.seed);
        // The room's option struct received the shared flags; the aerial defaults stand
        // where a flag was not given (its own resolution and image count).
        const RenderedSceneOptions& r = a.render_options;
        if (sub->count("--images")) o.image.num_images = a.options.num_images;
        if (sub->count("--width")) o.image.width = r.width;
        if (sub->count("--height")) o.image.height = r.height;
        if (sub->count("--focal")) o.image.focal_px = r.focal_px;
        if (sub->count("--supersampling")) o.image.supersampling = r.supersampling;
        if (sub->count("--image-noise")) o.image.image_noise = r.image_noise;
        if (sub->count("--strips")) {
          if (a.options.num_strips < 1)
            ThrowInputError("--strips", 0, "must be >= 1, got " + std::to_string(a.options.num_strips));
          o.strips = a.options.num_strips;
        }
        o.image.k1 = a.options.k1;
        o.image.focal_prior_error = a.options.focal_prior_error;
        ValidateAerialBlockOptions(o);
        return RunRenderAerial(a);
      }
      if (a.scene != "room" && a.scene != "object")
        ThrowInputError("--scene", 0, "unknown scene '" + a.scene + "' (room, object, aerial)");
      for (const char* opt : kAerialOnly)
        if (sub->count(opt)) ThrowInputError(opt, 0, "only applies with --scene aerial");
      if (sub->count("--strips")) ThrowInputError("--strips", 0, "only applies with --scene aerial");
      if (sub->count("--images")) a.render_options.num_images = a.options.num_images;
      a.render_options.k1 = a.options.k1;
      a.render_options.focal_prior_error = a.options.focal_prior_error;
      return RunRender(a);
    }
    for (const char* opt : kRenderOnly)
      if (sub->count(opt)) ThrowInputError(opt, 0, "only applies with --render");
    for (const char* opt : kAerialOnly)
      if (sub->count(opt)) ThrowInputError(opt, 0, "only applies with --render --scene aerial");
    if (!sub->count("--scenario")) ThrowInputError("--scenario", 0, "required (or --render for rendered images)");
    if (sub->count("--images") && a.options.num_images < 3)
      ThrowInputError("--images", 0, "must be >= 3, got " + std::to_string(a.options.num_images));
    if (sub->count("--points") && a.options.num_points < 1)
      ThrowInputError("--points", 0, "must be >= 1, got " + std::to_string(a.options.num_points));
    if (sub->count("--strips") && a.options.num_strips < 1)
      ThrowInputError("--strips", 0, "must be >= 1, got " + std::to_string(a.options.num_strips));
    a.options.seed = static_cast<uint64_t>(a.seed);
    if (!(a.options.noise_px >= 0.0 && std::isfinite(a.options.noise_px)))
      ThrowInputError("--noise", 0, "must be a finite number >= 0 px");
    if (!(a.options.outlier_fraction >= 0.0 && a.options.outlier_fraction < 1.0))
      ThrowInputError("--outliers", 0, "must be in [0, 1)");
    synthetic::ValidateLensOptions(a.options.k1, "--k1", a.options.focal_prior_error, "--focal-prior-error");
    return RunSynth(a);
  });
}

}  // namespace pgba::app
