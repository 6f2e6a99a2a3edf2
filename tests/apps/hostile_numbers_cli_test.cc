// Hostile numbers: NaN, inf, out-of-range and implausible values in options, configs,
// calibrations and the files converters write are refused with a message naming the file
// (or the option) and the value.
#include <gtest/gtest.h>
#include <climits>
#include <cmath>
#include <cstdint>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "tests/apps/hostile_cli_fixture.h"
#include "tests/support/colmap_database_writer.h"

namespace {
namespace fs = std::filesystem;
using pgba::test::Bytes;
using pgba::test::Lines;

class HostileNumbersCli : public pgba::test::HostileCli {};

// Silent wrong answer: options outside their domain ran and degraded the result; 1e999 gave
// a raw JSON exception without the file; duplicate keys were silently resolved.
TEST_F(HostileNumbersCli, ConfigOutOfRangeOverflowingOrAmbiguous) {
  struct Case {
    std::string json, problem;
  };
  const std::vector<Case> cases = {
      {R"({"local_hessian": {"huber_px": -1}})", "local_hessian.huber_px = -1 is out of range (> 0)"},
      {R"({"triplets": {"outlier_threshold_px": 0}})", "triplets.outlier_threshold_px = 0 is out of range (> 0)"},
      {R"({"global_ba": {"max_iterations": 1e999}})", "number overflow"},
      {R"({"pairs": {"min_inliers": 30, "min_inliers": 5}})", "duplicate key"},
  };
  const fs::path config = dir_ / "config.json";
  const std::string tracks = " --tracks " + (dir_ / "scene" / "input").string();
  for (const Case& c : cases) {
    std::ofstream(config, std::ios::trunc) << c.json;
    ExpectOneLineError(Run("reconstruct" + tracks + " --out " + (dir_ / "cfg_out").string() + " --config " +
                           config.string()),
                       config.string(), c.problem);
    ExpectOneLineError(Run("init" + tracks + " --out " + (dir_ / "cfg_ws").string() + " --config " + config.string()),
                       config.string(), c.problem);
    EXPECT_FALSE(fs::exists(dir_ / "cfg_out" / "sparse")) << c.json;
  }
}

// Silent wrong answer: a distortion that is not invertible over the image (SIMPLE_RADIAL
// k = -40) was accepted, as a calibration and in a tracks model.
TEST_F(HostileNumbersCli, NonInvertibleDistortion) {
  const fs::path images = Photos("folded_images"), calib = dir_ / "folded_cameras.txt";
  std::ofstream(calib) << "1 SIMPLE_RADIAL 320 240 300 160 120 -40\n";
  ExpectOneLineError(Run("features --images " + images.string() + " --calib " + calib.string() + " --out " +
                         (dir_ / "folded_ws").string()),
                     calib.string(), "not invertible");
  const fs::path model = ModelCopy("folded_model");
  std::vector<std::string> lines;
  {
    std::ifstream in(model / "cameras.txt");
    for (std::string line; std::getline(in, line);) lines.push_back(line);
  }
  size_t line_number = 0;
  for (size_t i = 0; i < lines.size() && line_number == 0; ++i) {
    if (lines[i].empty() || lines[i][0] == '#') continue;
    std::istringstream in(lines[i]);
    std::string id, model_name, f;
    int width = 0, height = 0;
    in >> id >> model_name >> width >> height >> f;  // the first parameter is a focal in every model
    lines[i] = id + " SIMPLE_RADIAL " + std::to_string(width) + " " + std::to_string(height) + " " + f + " " +
               std::to_string(width / 2) + " " + std::to_string(height / 2) + " -40";
    line_number = i + 1;
  }
  ASSERT_GT(line_number, 0u);
  {
    std::ofstream out(model / "cameras.txt", std::ios::trunc);
    for (const std::string& line : lines) out << line << '\n';
  }
  ExpectOneLineError(Run("reconstruct --tracks " + model.string() + " --out " + (dir_ / "folded_out").string()),
                     (model / "cameras.txt").string() + ":" + std::to_string(line_number), "not invertible");
}

// The command-line numbers that set config options are held to the same ranges as the
// config file (--threshold -1 ended in exit code 1 inside the RANSAC, --min-inliers -5 and
// --max-features 0 ran).
TEST_F(HostileNumbersCli, NumericFlagsAreHeldToTheirConfigRange) {
  struct Case {
    std::string args, message;
  };
  const std::string ws = " --out " + (dir_ / "flags_ws").string();
  const std::vector<Case> cases = {
      {"match" + ws + " --threshold -1",
       "--threshold: -1 is out of range (> 0; config key matching.verification.relative_pose.threshold_px)"},
      {"match" + ws + " --min-inliers -5", "--min-inliers: -5 is out of range (>= 5"},
      {"match" + ws + " --window 0", "--window: 0 is out of range (>= 1"},
      {"match" + ws + " --neighbors -2", "--neighbors: -2 is out of range (>= 1"},
      {"features --images " + (dir_ / "nowhere").string() + ws + " --max-features 0",
       "--max-features: 0 is out of range (>= 1"},
  };
  for (const Case& c : cases) {
    const pgba::test::CliResult r = Run(c.args);
    EXPECT_EQ(r.code, 2) << c.args << ": " << r.output;
    EXPECT_EQ(r.output.rfind("error: " + c.message, 0), 0u) << c.args << ": " << r.output;
  }
  EXPECT_FALSE(fs::exists(dir_ / "flags_ws"));
}

// A line of whitespace the tokenizer splits on ("\r\r", found by libFuzzer in
// fuzz_gcp_file) is a blank line: handed to the GCP parser with no token, it would be indexed
// past its end (SIGSEGV in reconstruct --gcp).
TEST_F(HostileNumbersCli, WhitespaceOnlyLineInGcpFile) {
  const fs::path gcp = dir_ / "gcp.txt";
  std::ofstream(gcp, std::ios::binary) << "\r\r\n\v\f\nGCP g 1 2 3 oops\n";
  ExpectOneLineError(Run("reconstruct --tracks " + (dir_ / "scene" / "input").string() + " --out " +
                         (dir_ / "gcp_out").string() + " --gcp " + gcp.string()),
                     gcp.string() + ":3", "sigma");
  EXPECT_FALSE(fs::exists(dir_ / "gcp_out" / "sparse"));
}

// Non-finite numbers are refused: a NaN option (which would run and print "inlier fraction
// 0.0000") and NaN keypoints of a database (which would go into tracks/).
TEST_F(HostileNumbersCli, NonFiniteNumbersAreRefused) {
  const std::string tracks = " --tracks " + (dir_ / "scene" / "input").string();
  for (const std::string& value : {std::string("nan"), std::string("inf"), std::string("NaN")}) {
    const pgba::test::CliResult a = Run("init" + tracks + " --out " + (dir_ / "nan_ws").string() +
                                        " --rotation-outliers " + value);
    EXPECT_EQ(a.code, 2) << a.output;
    EXPECT_EQ(a.output.rfind("error: --rotation-outliers: ", 0), 0u) << a.output;
    const pgba::test::CliResult e = Run("evaluate " + (dir_ / "scene" / "gt").string() + " --obs " +
                                        (dir_ / "scene" / "input").string() + " --inlier-px " + value);
    EXPECT_EQ(e.code, 2) << e.output;
    EXPECT_EQ(e.output.rfind("error: --inlier-px: ", 0), 0u) << e.output;
    if (value != "inf") {
      EXPECT_NE(e.output.find("expected a finite number, got '" + value + "'"), std::string::npos);
    }
  }
  const pgba::test::CliResult c =
      Run("convert eth3d-slam --sequence " + dir_.string() + " --out " + (dir_ / "nan_ds").string() + " --max-dt nan");
  EXPECT_EQ(c.code, 2) << c.output;
  EXPECT_NE(c.output.find("--max-dt"), std::string::npos) << c.output;
  const fs::path db = dir_ / "nan_keypoints.db";
  {
    pgba::test::DbWriter w(db.string());
    w.Camera(1, 1, 100, 100, {90, 90, 50, 50});
    w.Image(1, "a.jpg", 1);
    w.Image(2, "b.jpg", 1);
    w.Keypoints(1, 1, 2, {std::nanf(""), 20.f});
    w.Keypoints(2, 1, 2, {30.f, 40.f});
    w.TwoView(1, 2, {{0, 0}}, 2);
  }
  ExpectOneLineError(Run("match --database " + db.string() + " --out " + (dir_ / "nan_db_ws").string()), db.string(),
                     "keypoints of image 1: keypoint 0 is not finite");
  EXPECT_FALSE(fs::exists(dir_ / "nan_db_ws" / "tracks"));
}

// Converters checked what they wrote no more than a reader does: a zero focal, a PNG width
// read as -2147483648, a calibration of another size than the photos, an image listed twice.
TEST_F(HostileNumbersCli, ConvertersValidateWhatTheyWrite) {
  const fs::path seq = dir_ / "slam_seq";
  fs::create_directories(seq / "rgb");
  auto png = [](int w, int h) {
    std::string b = std::string("\x89PNG\r\n\x1a\n", 8) + std::string("\0\0\0\x0dIHDR", 8);
    for (unsigned v : {static_cast<unsigned>(w), static_cast<unsigned>(h)})
      for (int shift : {24, 16, 8, 0}) b.push_back(static_cast<char>((v >> shift) & 0xff));
    return b + std::string(5, '\0');
  };
  std::ofstream(seq / "rgb" / "1.png", std::ios::binary) << png(640, 480);
  std::ofstream(seq / "rgb.txt") << "1.0 rgb/1.png\n";
  std::ofstream(seq / "groundtruth.txt") << "1.0 0 0 0 0 0 0 1\n";
  std::ofstream(seq / "calibration.txt") << "0 0 320 240\n";
  const std::string slam = "convert eth3d-slam --sequence " + seq.string() + " --out ";
  ExpectOneLineError(Run(slam + (dir_ / "slam_out").string()), (seq / "calibration.txt").string(),
                     "focal length must be positive");
  std::ofstream(seq / "calibration.txt", std::ios::trunc) << "500 500 320 240\n";
  std::ofstream(seq / "rgb" / "1.png", std::ios::binary | std::ios::trunc) << png(INT32_MIN, 480);
  ExpectOneLineError(Run(slam + (dir_ / "slam_out").string()), (seq / "rgb" / "1.png").string(),
                     "declares a size of 2147483648x480");
  EXPECT_FALSE(fs::exists(dir_ / "slam_out"));

  const fs::path images = Photos("tanks_src");
  const fs::path log = dir_ / "tanks_src.log", cams = dir_ / "tanks_src_cameras.txt";
  {
    std::ofstream out(log);
    for (int i = 0; i < 3; ++i) out << i << " " << i << " 0\n1 0 0 " << i << "\n0 1 0 0\n0 0 1 0\n0 0 0 1\n";
  }
  std::ofstream(cams) << "1 PINHOLE 640 480 500 500 320 240\n";
  const std::string tanks =
      "convert tanks --log " + log.string() + " --images " + images.string() + " --cameras " + cams.string();
  ExpectOneLineError(Run(tanks + " --out " + (dir_ / "tanks_out").string()), (images / "im0.jpg").string(),
                     "photo is 320x240 but camera 1 is 640x480");
  std::ofstream(cams, std::ios::trunc) << "1 PINHOLE 320 240 300 300 160 120\n";
  const fs::path list = dir_ / "tanks_list.txt";
  std::ofstream(list) << "im0.jpg\nim1.jpg\nim0.jpg\n";
  ExpectOneLineError(Run(tanks + " --image-list " + list.string() + " --out " + (dir_ / "tanks_out").string()),
                     list.string() + ":3", "image im0.jpg listed twice");
  EXPECT_FALSE(fs::exists(dir_ / "tanks_out"));
  EXPECT_EQ(Run(tanks + " --out " + (dir_ / "tanks_out").string()).code, 0);
  // A symbolic link loop among the photos: one line naming it, not a raw filesystem error.
  fs::create_symlink(images / "loop_b.jpg", images / "loop_a.jpg");
  fs::create_symlink(images / "loop_a.jpg", images / "loop_b.jpg");
  ExpectOneLineError(Run(tanks + " --out " + (dir_ / "tanks_loop_out").string()), (images / "loop_").string(),
                     "cannot access");
}

// Unsigned options out of their type or sign ("-5", which would read as 2^64 - 5; 10^23 as a
// benchmark's seed, 2^64 - 1; values CLI11's positive-number check would print as the largest
// double in 300 digits): each is one short line naming the option and the value.
TEST_F(HostileNumbersCli, OptionsOutOfTheirTypeOrSignAreRefused) {
  struct Case {
    std::string args, message;
  };
  const std::string tracks = (dir_ / "scene" / "input").string(), gt = (dir_ / "scene" / "gt").string();
  const std::string benchmark = "benchmark --tracks " + tracks + " --out " + (dir_ / "seed_out").string();
  const std::vector<Case> cases = {
      {benchmark + " --perturb-seed -5", "error: --perturb-seed: expected a non-negative integer, got '-5'"},
      {benchmark + " --perturb-seed 99999999999999999999999", "error: --perturb-seed: 99999999999999999999999 is out"},
      {"evaluate " + gt + " --obs " + tracks + " --inlier-px 0", "error: --inlier-px: must be > 0, got '0'"},
      {"evaluate " + gt + " --obs " + tracks + " --inlier-px -1e400", "error: --inlier-px: "},
      {"convert eth3d-slam --sequence " + tracks + " --out " + (dir_ / "seed_ds").string() + " --max-dt -1",
       "error: --max-dt: must be >= 0, got '-1'"},
  };
  for (const Case& c : cases) {
    const pgba::test::CliResult r = Run(c.args);
    EXPECT_EQ(r.code, 2) << c.args << ": " << r.output;
    ASSERT_EQ(Lines(r.output).size(), 1u) << r.output;
    EXPECT_EQ(r.output.rfind(c.message, 0), 0u) << c.args << ": " << r.output;
    EXPECT_LT(r.output.size(), 200u) << r.output;
  }
  EXPECT_FALSE(fs::exists(dir_ / "seed_out" / "benchmark.json"));
}

}  // namespace
