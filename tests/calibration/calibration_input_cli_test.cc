// Bad calibrations, from the built binary: a calibration file that fixes a camera model
// pgba cannot refine (COLMAP's fisheye and full OpenCV models: no projection of theirs is
// implemented, so neither held nor refined), as cameras.txt and as JSON, or whose distortion
// is not invertible over the image (also when the file is only a prior, --calib-prior), ends
// `pgba run` with exit code 2 and one line "error: FILE...: problem", before any work.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "tests/apps/cli_runner.h"

namespace {
namespace fs = std::filesystem;

class CalibrationInputCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("pgba_calib_input_cli_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_ / "images");
    for (int i = 0; i < 3; ++i) {  // three textured photos, no calibration beside them
      cv::Mat img(240, 320, CV_8U);
      cv::RNG rng(20 + i);
      rng.fill(img, cv::RNG::UNIFORM, 0, 256);
      cv::GaussianBlur(img, img, cv::Size(0, 0), 2.0);
      cv::imwrite((dir_ / "images" / ("im" + std::to_string(i) + ".png")).string(), img);
    }
  }
  void TearDown() override { fs::remove_all(dir_); }

  // `pgba run` on the photos with `calib` holding `text`, plus `extra` arguments.
  pgba::test::CliResult RunWith(const std::string& file, const std::string& text, const std::string& extra = "") {
    std::ofstream(dir_ / file) << text;
    return pgba::test::RunPgbaWithin(120, "-v 0 run --images " + (dir_ / "images").string() + " --calib " +
                                              (dir_ / file).string() + " " + extra + " --out " +
                                              (dir_ / "out").string());
  }

  // Exit 2 and exactly one line, "error: " + a message naming `file` and `problem`; no
  // features were computed (the calibration is read first).
  void ExpectOneLineError(const pgba::test::CliResult& r, const std::string& file, const std::string& problem) {
    EXPECT_EQ(r.code, 2) << r.output;
    std::vector<std::string> lines;
    std::istringstream in(r.output);
    for (std::string line; std::getline(in, line);)
      if (!line.empty()) lines.push_back(line);
    ASSERT_EQ(lines.size(), 1u) << r.output;
    EXPECT_EQ(lines[0].rfind("error: ", 0), 0u) << lines[0];
    EXPECT_NE(lines[0].find((dir_ / file).string()), std::string::npos) << "does not name " << file << ": " << lines[0];
    EXPECT_NE(lines[0].find(problem), std::string::npos) << lines[0];
    EXPECT_FALSE(fs::exists(dir_ / "out" / "features" / "im0.png.bin"));
  }

  fs::path dir_;
};

TEST_F(CalibrationInputCli, ModelPgbaCannotRefineInCamerasTxt) {
  for (const char* line : {"1 OPENCV_FISHEYE 320 240 300 300 160 120 0.01 0 0 0\n",
                           "1 FULL_OPENCV 320 240 300 300 160 120 0 0 0 0 0 0 0 0\n"}) {
    SCOPED_TRACE(line);
    for (const char* extra : {"", "--calib-prior"})
      ExpectOneLineError(RunWith("cameras.txt", line, extra), "cameras.txt", "unsupported camera model");
  }
}

TEST_F(CalibrationInputCli, ModelPgbaCannotRefineInJson) {
  ExpectOneLineError(RunWith("calib.json", R"({"cameras": [{"camera_id": 1, "model": "SIMPLE_RADIAL_FISHEYE",
      "width": 320, "height": 240, "params": [300, 160, 120, 0.01]}]})",
                             "--calib-prior"),
                     "calib.json", "SIMPLE_RADIAL_FISHEYE");
}

// k = -40 folds the image over a few pixels from the centre: no bearing for most pixels. As a
// prior it would be the start of the self-calibration, which must not begin from it either.
TEST_F(CalibrationInputCli, DistortionNotInvertibleOverTheImage) {
  for (const char* extra : {"", "--calib-prior"}) {
    SCOPED_TRACE(extra);
    ExpectOneLineError(RunWith("cameras.txt", "1 SIMPLE_RADIAL 320 240 300 160 120 -40\n", extra), "cameras.txt",
                       "not invertible");
    ExpectOneLineError(RunWith("cameras_opencv.txt", "1 OPENCV 320 240 300 300 160 120 -40 0 0 0\n", extra),
                       "cameras_opencv.txt", "not invertible");
  }
}

}  // namespace
