// `pgba synth` end to end: writes gt/, input/ and loop_pairs.txt that read back into the
// scene the library generates; `--render` writes the image dataset layout; bad arguments
// exit with code 2 and a one-line error.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "modules/synthetic/rendered_scene.h"
#include "modules/synthetic/synthetic_scene.h"
#include "pgba/io/colmap_text.h"
#include "pgba/io/loop_pairs.h"
#include "tests/apps/cli_runner.h"

namespace pgba {
namespace {
namespace fs = std::filesystem;

using test::CliResult;
using test::RunPgba;

fs::path TempDir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("pgba_synth_cli_" + std::to_string(::getpid()) + "_" + name);
  fs::remove_all(d);
  return d;
}

TEST(SynthCli, WritesGroundTruthInputAndLoopPairs) {
  const fs::path out = TempDir("longfocal");
  const CliResult r =
      RunPgba("synth --scenario longfocal --out " + out.string() + " --seed 5 --noise 0.3 --outliers 0.02");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("93 images"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("mean track length"), std::string::npos) << r.output;

  SyntheticOptions o;
  o.scenario = SyntheticScenario::kLongFocal;
  o.seed = 5;
  o.noise_px = 0.3;
  o.outlier_fraction = 0.02;
  const SyntheticScene expected = GenerateSyntheticScene(o);
  const Reconstruction gt = ReadColmapText((out / "gt").string());
  const Reconstruction input = ReadColmapText((out / "input").string());
  EXPECT_EQ(gt.images.size(), 93u);
  EXPECT_EQ(gt.points3D.size(), expected.gt.points3D.size());
  EXPECT_EQ(gt.NumObservations(), expected.gt.NumObservations());
  EXPECT_EQ(input.NumObservations(), expected.gt.NumObservations());
  EXPECT_EQ(gt.images.at(7).pose.t(), expected.gt.images.at(7).pose.t());
  EXPECT_EQ(input.images.at(7).pose.t(), Eigen::Vector3d::Zero());
  const auto loop = ReadLoopPairs((out / "loop_pairs.txt").string());
  ASSERT_EQ(loop.size(), expected.loop_pairs.size());
  EXPECT_EQ(loop.front().xy_i, expected.loop_pairs.front().xy_i);

  // Re-running another scenario into the same directory leaves no stale loop file behind.
  ASSERT_EQ(RunPgba("synth --scenario planar --images 10 --out " + out.string()).code, 0);
  EXPECT_FALSE(fs::exists(out / "loop_pairs.txt"));
  EXPECT_EQ(ReadColmapText((out / "gt").string()).images.size(), 10u);
  fs::remove_all(out);
}

TEST(SynthCli, LensDistortionAndAWrongFocalPrior) {
  const fs::path out = TempDir("lens");
  const CliResult r = RunPgba("synth --scenario orbit --images 12 --k1 -0.08 --focal-prior-error 0.15 --out " +
                              out.string());
  ASSERT_EQ(r.code, 0) << r.output;
  const Reconstruction gt = ReadColmapText((out / "gt").string());
  const Reconstruction input = ReadColmapText((out / "input").string());
  const Camera& truth = gt.cameras.at(1);
  const Camera& prior = input.cameras.at(1);
  ASSERT_EQ(truth.model, CameraModel::kSimpleRadial);
  EXPECT_EQ(truth.params, (std::vector<double>{1163.0, 960.0, 540.0, -0.08}));
  ASSERT_EQ(prior.model, CameraModel::kSimpleRadial);
  EXPECT_DOUBLE_EQ(prior.params[0], 1.15 * 1163.0);
  EXPECT_EQ(prior.params[3], 0.0);
  // The observations written are the truth's projections (noise 0.5 px).
  double sum2 = 0.0;
  size_t n = 0;
  for (const auto& [id, im] : gt.images)
    for (const Point2D& obs : im.points2D) {
      const Eigen::Vector2d px = truth.Project(im.pose.ToCamera(gt.points3D.at(obs.point3D_id).xyz));
      sum2 += (px - obs.xy).squaredNorm();
      ++n;
    }
  ASSERT_GT(n, 100u);
  EXPECT_NEAR(std::sqrt(sum2 / (2.0 * n)), 0.5, 0.05);
  fs::remove_all(out);
}

TEST(SynthCli, BadArgumentsExitWithCode2) {
  const fs::path out = TempDir("bad");
  // {arguments, what the one-line error must name}
  const std::vector<std::pair<std::string, std::string>> cases = {{"--scenario temple", "temple"},
                                                                  {"--scenario orbit --noise -1", "--noise"},
                                                                  {"--scenario orbit --outliers 1", "--outliers"},
                                                                  {"--scenario orbit --outliers -0.2", "--outliers"},
                                                                  {"--scenario orbit --images 2", "--images"},
                                                                  {"--scenario orbit --images 0", "--images"},
                                                                  {"--scenario orbit --noise abc", "--noise"},
                                                                  {"--scenario aerial --strips 0", "--strips"},
                                                                  {"--scenario orbit --seed -3", "--seed"},
                                                                  {"--scenario orbit --noise nan", "--noise"},
                                                                  {"--scenario orbit --k1 5", "--k1"},
                                                                  {"--scenario orbit --k1 -0.9", "not invertible"},
                                                                  {"--scenario orbit --focal-prior-error 2", "--focal-prior-error"},
                                                                  {"--scenario orbit --focal-prior-error -0.7", "--focal-prior-error"}};
  for (const auto& [args, names] : cases) {
    const CliResult r = RunPgba("synth " + args + " --out " + out.string());
    EXPECT_EQ(r.code, 2) << args << ": " << r.output;
    EXPECT_NE(r.output.find(names), std::string::npos) << args << ": " << r.output;
  }
  EXPECT_FALSE(fs::exists(out / "gt"));
}

TEST(SynthCli, RenderWritesImagesCalibrationGroundTruthAndLoop) {
  const fs::path out = TempDir("render");
  const CliResult r = RunPgba("synth --render --images 4 --width 128 --height 96 --seed 3 --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("4 images 128x96"), std::string::npos) << r.output;
  RenderedSceneOptions o;
  o.num_images = 4;
  o.width = 128;
  o.height = 96;
  o.seed = 3;
  const RenderedScene expected = RenderRoomScene(o);
  const Reconstruction gt = ReadColmapText((out / "gt").string());
  ASSERT_EQ(gt.images.size(), 4u);
  for (const auto& [id, im] : gt.images) {
    EXPECT_EQ(im.name, expected.gt.images.at(id).name);
    EXPECT_LT((im.pose.C() - expected.gt.images.at(id).pose.C()).norm(), 1e-12);
    const cv::Mat img = cv::imread((out / "images" / im.name).string(), cv::IMREAD_UNCHANGED);
    ASSERT_FALSE(img.empty()) << im.name;
    EXPECT_EQ(cv::norm(img, expected.images[id - 1], cv::NORM_INF), 0.0) << im.name;
  }
  EXPECT_TRUE(fs::exists(out / "cameras.txt"));
  EXPECT_TRUE(fs::exists(out / "loop.txt"));
  // Fewer images into the same folder: no stale image is left to join the set.
  ASSERT_EQ(RunPgba("synth --render --images 3 --width 128 --height 96 --out " + out.string()).code, 0);
  EXPECT_EQ(std::distance(fs::directory_iterator(out / "images"), fs::directory_iterator()), 3);
  fs::remove_all(out);
}

TEST(SynthCli, RenderBadArgumentsExitWithCode2) {
  const fs::path out = TempDir("render_bad");
  const std::vector<std::pair<std::string, std::string>> cases = {{"--render --images 2", "--images"},
                                                                  {"--render --noise 1", "--noise"},
                                                                  {"--render --scenario orbit", "--scenario"},
                                                                  {"--render --supersampling 0", "--supersampling"},
                                                                  {"--render --width 8", "--width"},
                                                                  {"--render --focal -5", "--focal"},
                                                                  {"--render --image-noise -1", "--image-noise"},
                                                                  {"--render --k1 -0.95", "--k1"},
                                                                  {"--render --focal-prior-error nan", "--focal-prior-error"},
                                                                  {"--scenario orbit --width 320", "--width"},
                                                                  {"--seed 2", "--scenario"}};
  for (const auto& [args, names] : cases) {
    const CliResult r = RunPgba("synth " + args + " --out " + out.string());
    EXPECT_EQ(r.code, 2) << args << ": " << r.output;
    EXPECT_NE(r.output.find(names), std::string::npos) << args << ": " << r.output;
  }
  EXPECT_FALSE(fs::exists(out / "images"));
}

}  // namespace
}  // namespace pgba
