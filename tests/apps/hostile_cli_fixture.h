// The hostile-input CLI tests (tests/apps/hostile_*_cli_test.cc, one file per class of case:
// names, ids, numbers, paths and outputs, caches, messages) run the built binary as a hostile
// user would: every case ends in exit code 2 and one line "error: FILE...: problem" (or,
// where the run can go on, exit 0 and a warning naming the file), with no signal, no hang
// (each run under `timeout`) and nothing left that reads as a result. Cases that other CLI
// tests run end to end live there:
//   workspace of another scene / other options    reconstruct_cli_test.cc WorkspaceOfOtherScene...
//   failed re-run of reconstruct, stale outputs   reconstruct_cli_test.cc FailedReRunLeavesNoStaleResult
//   bad --out of reconstruct found before work    reconstruct_cli_test.cc BadOutIsAnErrorBeforeAnyWork
//   evaluate --gt with no image in common         evaluate_cli_test.cc GroundTruthWithNoImageInCommon...
//   failed re-run of run, stale outputs           determinism_cli_test.cc (the run pair)
//   1 vs 2 threads byte-identical                 determinism_cli_test.cc
#pragma once

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

namespace pgba::test {

inline std::string Bytes(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// The non-empty lines of `text`.
inline std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);)
    if (!line.empty()) lines.push_back(line);
  return lines;
}

// A scratch folder per test suite with a small synthetic scene (`scene/gt`, `scene/input`: an
// aerial block of 12 images) that the cases copy and damage.
class HostileCli : public ::testing::Test {
 protected:
  static constexpr int kTimeoutSeconds = 120;

  static void SetUpTestSuite() {
    dir_ = std::filesystem::temp_directory_path() / ("pgba_hostile_cli_" + std::to_string(::getpid()));
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
    ASSERT_EQ(Run("synth --scenario aerial --images 12 --seed 5 --out " + (dir_ / "scene").string()).code, 0);
  }
  static void TearDownTestSuite() { std::filesystem::remove_all(dir_); }

  static CliResult Run(const std::string& args) { return RunPgbaWithin(kTimeoutSeconds, "-v 0 " + args); }

  // Exit 2 and exactly one line, "error: " + a message naming `file` and `problem`.
  static void ExpectOneLineError(const CliResult& r, const std::string& file, const std::string& problem) {
    EXPECT_NE(r.code, 124) << "hang: " << r.output;
    EXPECT_EQ(r.code, 2) << r.output;
    const std::vector<std::string> lines = Lines(r.output);
    ASSERT_EQ(lines.size(), 1u) << r.output;
    EXPECT_EQ(lines[0].rfind("error: ", 0), 0u) << lines[0];
    EXPECT_NE(lines[0].find(file), std::string::npos) << "does not name " << file << ": " << lines[0];
    EXPECT_NE(lines[0].find(problem), std::string::npos) << lines[0];
  }

  // A copy of the scene's tracks model in `name`/, for a case to damage.
  static std::filesystem::path ModelCopy(const std::string& name) {
    const std::filesystem::path copy = dir_ / name;
    std::filesystem::remove_all(copy);
    std::filesystem::copy(dir_ / "scene" / "input", copy, std::filesystem::copy_options::recursive);
    return copy;
  }

  // NAME/images/: three textured 320 x 240 photos; their calibration NAME/cameras.txt is found
  // in the folder's parent.
  static std::filesystem::path Photos(const std::string& name) {
    const std::filesystem::path images = dir_ / name / "images";
    std::filesystem::create_directories(images);
    for (int i = 0; i < 3; ++i) {
      cv::Mat img(240, 320, CV_8U);
      cv::RNG rng(10 + i);
      rng.fill(img, cv::RNG::UNIFORM, 0, 256);
      cv::GaussianBlur(img, img, cv::Size(0, 0), 2.0);
      cv::imwrite((images / ("im" + std::to_string(i) + ".jpg")).string(), img);
    }
    std::ofstream(dir_ / name / "cameras.txt") << "1 PINHOLE 320 240 300 300 160 120\n";
    return images;
  }

  inline static std::filesystem::path dir_;
};

}  // namespace pgba::test
