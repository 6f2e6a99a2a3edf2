// The result does not depend on the thread count or on the output path: `pgba reconstruct`
// with --threads 1 and --threads 2, into folders of different name lengths (heap layouts
// differ with them), writes byte-identical sparse/ models and points.ply.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "tests/apps/cli_runner.h"

namespace {
namespace fs = std::filesystem;

std::string Bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

class DeterminismCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("pgba_determinism_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  static pgba::test::CliResult Run(const std::string& args) { return pgba::test::RunPgba("-v 0 " + args); }
  fs::path dir_;
};

TEST_F(DeterminismCli, ReconstructIsByteIdenticalForOneAndTwoThreadsAndAnyOutPath) {
  ASSERT_EQ(Run("synth --scenario aerial --images 24 --seed 3 --noise 0.5 --outliers 0.02 --out " +
                (dir_ / "scene").string())
                .code,
            0);
  const std::string tracks = " --tracks " + (dir_ / "scene" / "input").string();
  const fs::path one = dir_ / "a", two = dir_ / "a_much_longer_output_folder_name_for_another_heap_layout";
  pgba::test::CliResult r = Run("--threads 1 reconstruct" + tracks + " --out " + one.string());
  ASSERT_EQ(r.code, 0) << r.output;
  r = Run("--threads 2 reconstruct" + tracks + " --out " + two.string());
  ASSERT_EQ(r.code, 0) << r.output;
  for (const char* f : {"sparse/cameras.txt", "sparse/images.txt", "sparse/points3D.txt", "points.ply",
                        "triplets.json", "local_hessians.json", "init/images.txt"}) {
    ASSERT_TRUE(fs::exists(one / f)) << f;
    EXPECT_TRUE(Bytes(one / f) == Bytes(two / f)) << f << " differs between 1 and 2 threads";
  }
}

TEST_F(DeterminismCli, ThreadsOptionIsValidated) {
  const pgba::test::CliResult r = Run("--threads -3 synth --scenario orbit --out " + (dir_ / "x").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("--threads"), std::string::npos) << r.output;
}

}  // namespace
