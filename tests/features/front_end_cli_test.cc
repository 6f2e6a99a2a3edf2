// `pgba features` / `pgba match` on bad input, through the binary: files the run can do
// without are skipped with a warning naming them; inputs it cannot do without stop it with
// a one-line "error: ..." and exit code 2; nothing crashes.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "tests/apps/cli_runner.h"

namespace pgba {
namespace {
namespace fs = std::filesystem;

using test::CliResult;
using test::RunPgba;

int CountLines(const std::string& s) { return static_cast<int>(std::count(s.begin(), s.end(), '\n')); }

class FrontEndCli : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::temp_directory_path() / ("pgba_front_cli_" + std::to_string(::getpid()) + "_" +
                                         ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(root_);
    fs::create_directories(root_ / "images");
    for (int i = 0; i < 3; ++i) {
      cv::Mat img(240, 320, CV_8U);
      cv::RNG(50 + i).fill(img, cv::RNG::UNIFORM, 0, 256);
      cv::GaussianBlur(img, img, cv::Size(0, 0), 2.0);
      cv::imwrite((root_ / "images" / ("im" + std::to_string(i) + ".png")).string(), img);
    }
    std::ofstream(root_ / "cameras.txt") << "1 PINHOLE 320 240 300 300 160 120\n";
  }
  void TearDown() override { fs::remove_all(root_); }
  std::string Features(const std::string& extra = "") {
    return "features --images " + (root_ / "images").string() + " --out " + (root_ / "ws").string() + extra;
  }
  fs::path root_;
};

TEST_F(FrontEndCli, SkipsUnusableFilesWithAWarningNamingEach) {
  std::ofstream(root_ / "images" / "readme.txt") << "not an image\n";
  std::ofstream(root_ / "images" / "fake.jpg") << std::string(500, 'z');
  fs::copy_file(root_ / "images" / "im0.png", root_ / "images" / "cut.png");
  fs::resize_file(root_ / "images" / "cut.png", fs::file_size(root_ / "images" / "cut.png") / 3);
  cv::imwrite((root_ / "images" / "other_size.png").string(), cv::Mat(300, 400, CV_8U, cv::Scalar(90)));
  const CliResult r = RunPgba(Features());
  ASSERT_EQ(r.code, 0) << r.output;
  for (const char* name : {"readme.txt", "fake.jpg", "cut.png", "other_size.png"})
    EXPECT_NE(r.output.find(std::string(name) + ": "), std::string::npos) << name << "\n" << r.output;
  EXPECT_NE(r.output.find("400x300"), std::string::npos) << r.output;
  std::ifstream in(root_ / "ws" / "report.json");
  const nlohmann::json report = nlohmann::json::parse(in);
  EXPECT_EQ(report["stages"]["features"]["images"], 3);
  EXPECT_EQ(report["stages"]["features"]["images_skipped"].size(), 4u);
  EXPECT_GT(report["stages"]["features"]["seconds_per_megapixel"].get<double>(), 0.0);
  EXPECT_GT(report["stages"]["features"]["cpu_seconds"].get<double>(), 0.0);
  // Matching goes on with the three good images.
  const CliResult m = RunPgba("match --out " + (root_ / "ws").string());
  EXPECT_EQ(m.code, 0) << m.output;
  // The pairs' threads' CPU time (descriptors, verification) is part of the process' CPU
  // time over the pair loop (two clocks: per thread and getrusage; 1 ms for their rounding).
  const nlohmann::json match = nlohmann::json::parse(std::ifstream(root_ / "ws" / "report.json"))["stages"]["match"];
  const double per_pair = match["cpu_seconds_per_pair"].get<double>();
  const double descriptors = match["cpu_seconds_per_pair_descriptors"].get<double>();
  EXPECT_GT(descriptors, 0.0);
  EXPECT_GE(per_pair + 1e-3, descriptors + match["cpu_seconds_per_pair_verification"].get<double>());
}

TEST_F(FrontEndCli, FatalInputsGiveOneLineErrors) {
  fs::create_directories(root_ / "empty");
  fs::create_directories(root_ / "nocalib" / "images");
  std::ofstream(root_ / "nocalib" / "images" / "notes.txt") << "no image to take a focal prior from\n";
  std::ofstream(root_ / "garbage_cameras.txt") << "1 PINHOLE 320 two hundred\n";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"features --images " + (root_ / "empty").string() + " --calib " + (root_ / "cameras.txt").string() +
           " --out " + (root_ / "ws").string(),
       "empty"},
      {"features --images " + (root_ / "nocalib" / "images").string() + " --out " + (root_ / "ws").string(),
       "calib"},
      {Features(" --calib " + (root_ / "missing.txt").string()), "missing.txt"},
      {Features(" --calib " + (root_ / "garbage_cameras.txt").string()), "garbage_cameras.txt"},
      {"features --images " + (root_ / "no_such_dir").string() + " --out " + (root_ / "ws").string(), "no_such_dir"},
      {"match --out " + (root_ / "no_workspace").string(), "features"},
  };
  for (const auto& [args, names] : cases) {
    const CliResult r = RunPgba(args);
    EXPECT_EQ(r.code, 2) << args << "\n" << r.output;
    EXPECT_EQ(r.output.rfind("error: ", 0), 0u) << args << "\n" << r.output;
    EXPECT_EQ(CountLines(r.output), 1) << args << "\n" << r.output;
    EXPECT_NE(r.output.find(names), std::string::npos) << args << "\n" << r.output;
  }
  // Every image of the wrong size for the one calibration: nothing left to work with.
  std::ofstream(root_ / "cameras.txt") << "1 PINHOLE 640 480 300 300 320 240\n";
  const CliResult r = RunPgba(Features());
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("error: "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("im1.png"), std::string::npos) << r.output;  // the warnings name the files
}

}  // namespace
}  // namespace pgba
