// `pgba evaluate` end to end on files written by the test: a good run writes the JSON with
// the report keys; bad inputs exit with code 2 and "error: FILE..." on stderr, writing nothing.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "pgba/io/colmap_text.h"
#include "pgba/io/loop_pairs.h"
#include "tests/apps/cli_runner.h"
#include "tests/evaluation/test_scene.h"

namespace pgba {
namespace {
namespace fs = std::filesystem;

std::string Slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

class EvaluateCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("pgba_eval_cli_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    scene_ = test::MakeTestScene(51, 10, 800, 0.5, 100);
    WriteColmapText(scene_.gt, (dir_ / "gt").string());
    // The input: same observations, poses unknown (identity).
    Reconstruction input = scene_.gt;
    for (auto& [id, im] : input.images) im.pose = Pose();
    for (auto& [id, p] : input.points3D) p.xyz.setZero();
    WriteColmapText(input, (dir_ / "input").string());
    // A ground truth without points3D.txt (poses only).
    WriteColmapText(scene_.gt, (dir_ / "gt_poses").string());
    fs::remove(dir_ / "gt_poses" / "points3D.txt");
    WriteLoopPairs(scene_.loops, (dir_ / "loop_pairs.txt").string());
  }
  void TearDown() override { fs::remove_all(dir_); }

  test::CliStreams Run(const std::string& args) { return test::RunPgbaStreams("evaluate " + args); }

  // Copies gt/ to a fresh bad_<k>/ with `file`'s line `line_no` (1-based, counting every
  // line) replaced.
  std::string CorruptCopy(const std::string& file, int line_no, const std::string& replacement) {
    const fs::path bad = dir_ / ("bad_" + std::to_string(num_copies_++));
    fs::remove_all(bad);
    fs::copy(dir_ / "gt", bad);
    std::ifstream in(bad / file);
    std::vector<std::string> lines;
    for (std::string l; std::getline(in, l);) lines.push_back(l);
    in.close();
    lines.at(line_no - 1) = replacement;
    std::ofstream o(bad / file);
    for (const auto& l : lines) o << l << "\n";
    return bad.string();
  }

  fs::path dir_;
  test::TestScene scene_;
  int num_copies_ = 0;
};

TEST_F(EvaluateCli, GoodRunWritesJsonWithTheKeys) {
  const fs::path json = dir_ / "res" / "eval.json";
  const test::CliStreams r = Run((dir_ / "gt").string() + " --obs " + (dir_ / "input").string() + " --gt " +
                          (dir_ / "gt_poses").string() + " --loop " + (dir_ / "loop_pairs.txt").string() +
                          " --json " + json.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("sigma rms (px)"), std::string::npos) << r.out;
  const nlohmann::json j = nlohmann::json::parse(Slurp(json));
  for (const char* key : {"images_input", "images_registered", "sigma_rms", "sigma_median", "inlier_fraction",
                          "rot_err_deg_median", "rot_err_deg_max", "center_err_rel_median", "center_err_rel_max",
                          "loop_err_rms", "loop_err_median"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_EQ(j["images_input"].get<int>(), 10);
  EXPECT_EQ(j["images_registered"].get<int>(), 10);
  // True poses: sigma at the noise level (0.5 px per coordinate -> ~0.55-0.65 px per 2D
  // residual for these track lengths), zero pose error (text round trip: 17 digits).
  EXPECT_GT(j["sigma_rms"].get<double>(), 0.4);
  EXPECT_LT(j["sigma_rms"].get<double>(), 0.75);
  EXPECT_LT(j["rot_err_deg_max"].get<double>(), 1e-6);
  EXPECT_LT(j["center_err_rel_max"].get<double>(), 1e-9);
  // 100 loop correspondences on true poses: RMS ~ 0.5 / sqrt(2) px.
  EXPECT_GT(j["loop_err_rms"].get<double>(), 0.25);
  EXPECT_LT(j["loop_err_rms"].get<double>(), 0.5);
  // Evaluating the input (identity poses) against itself: every centre coincides, so the
  // ground-truth alignment is undefined and its keys are absent; the run still succeeds.
  const test::CliStreams degenerate = Run((dir_ / "input").string() + " --obs " + (dir_ / "input").string() + " --gt " +
                                   (dir_ / "gt").string() + " --json " + json.string());
  ASSERT_EQ(degenerate.code, 0) << degenerate.err;
  const nlohmann::json k = nlohmann::json::parse(Slurp(json));
  EXPECT_FALSE(k.contains("rot_err_deg_max"));
  EXPECT_FALSE(k.contains("loop_err_rms"));  // no --loop
}

TEST_F(EvaluateCli, BadInputsExitTwoNamingTheFile) {
  const std::string obs = " --obs " + (dir_ / "input").string();
  const fs::path json = dir_ / "never.json";
  struct Case {
    std::string name, model, expect;
  };
  // images.txt: 4 header lines in WriteColmapText's output, then IMAGE line / POINTS2D line.
  const std::vector<Case> cases = {
      {"missing dir", (dir_ / "nope").string(), (dir_ / "nope").string() + ": model directory not found"},
      {"NaN in images.txt", CorruptCopy("images.txt", 5, "1 nan 0 0 0 0 0 0 1 img_0.jpg"), "images.txt:5:"},
      {"unknown camera model", CorruptCopy("cameras.txt", 4, "1 FISHEYE_XYZ 1280 960 800 640 480"),
       "cameras.txt:4: unknown or unsupported camera model"},
      {"truncated image line", CorruptCopy("images.txt", 5, "1 1 0 0"), "images.txt:5: truncated line"},
      {"truncated camera line", CorruptCopy("cameras.txt", 4, "1 PINHOLE"), "cameras.txt:4: truncated line"},
  };
  for (const Case& c : cases) {
    const test::CliStreams r = Run(c.model + obs + " --json " + json.string());
    EXPECT_EQ(r.code, 2) << c.name << ": " << r.err;
    EXPECT_EQ(r.err.rfind("error: ", 0), 0u) << c.name << ": " << r.err;
    EXPECT_NE(r.err.find(c.expect), std::string::npos) << c.name << ": " << r.err;
    EXPECT_FALSE(fs::exists(json)) << c.name;
  }
  // A bad observation or ground-truth model is reported the same way.
  const std::string bad_points = CorruptCopy("points3D.txt", 4, "1 0.5 0.5");
  test::CliStreams r = Run((dir_ / "gt").string() + " --obs " + bad_points + " --json " + json.string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("points3D.txt:4: truncated line"), std::string::npos) << r.err;
  r = Run((dir_ / "gt").string() + obs + " --gt " + (dir_ / "missing_gt").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("missing_gt: model directory not found"), std::string::npos) << r.err;
  std::ofstream(dir_ / "bad_loops.txt") << "img_0.jpg 1 2 img_5.jpg 3\n";
  r = Run((dir_ / "gt").string() + obs + " --loop " + (dir_ / "bad_loops.txt").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("bad_loops.txt:1: expected 6 fields"), std::string::npos) << r.err;
  r = Run((dir_ / "gt").string() + obs + " --inlier-px -1");
  EXPECT_EQ(r.code, 2) << r.err;
  r = Run((dir_ / "gt").string());  // --obs is required
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_FALSE(fs::exists(json));
  // An earlier result at --json does not survive a failed evaluation (it would read as its result).
  const fs::path earlier = dir_ / "earlier.json";
  std::ofstream(earlier) << "{\"images_registered\": 10}\n";
  r = Run((dir_ / "gt").string() + " --obs " + bad_points + " --json " + earlier.string());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_FALSE(fs::exists(earlier));
}

// A ground truth with no image in common is an error: exit 0 with "0 compared" would give
// errors over no image that read like a perfect score.
TEST_F(EvaluateCli, GroundTruthWithNoImageInCommonIsAnError) {
  Reconstruction renamed = scene_.gt;
  for (auto& [id, im] : renamed.images) im.name = "other_" + im.name;
  WriteColmapText(renamed, (dir_ / "gt_renamed").string());
  const fs::path json = dir_ / "none.json";
  const test::CliStreams r = Run((dir_ / "gt").string() + " --obs " + (dir_ / "input").string() + " --gt " +
                                 (dir_ / "gt_renamed").string() + " --json " + json.string());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("error: " + (dir_ / "gt_renamed").string() + ": no image in common with"), std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(json));
}

// An unknown subcommand is named as such, with the known ones.
TEST(PgbaCli, UnknownCommandIsNamed) {
  const test::CliStreams r = test::RunPgbaStreams("-v 0 reconstrct --tracks x --out y");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("error: unknown command 'reconstrct' (commands: synth, evaluate,"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << r.err;  // one line
}

}  // namespace
}  // namespace pgba
