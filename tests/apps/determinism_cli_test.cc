// The result does not depend on the thread count or on the output path: `pgba reconstruct`
// and `pgba run` with --threads 1 and --threads 2, into folders of different name lengths
// (heap layouts differ with them), write byte-identical sparse/ models, points.ply and
// workspace files.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

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

// The initialisation with the (optional) track positioning, a Ceres solve over centres and
// points of its own, is as independent of the thread count and the heap layout.
TEST_F(DeterminismCli, InitWithTrackPositioningIsByteIdenticalForOneAndTwoThreads) {
  ASSERT_EQ(Run("synth --scenario aerial --images 24 --seed 3 --noise 0.5 --outliers 0.02 --out " +
                (dir_ / "scene").string())
                .code,
            0);
  const fs::path config = dir_ / "track_positioning.json";
  std::ofstream(config) << R"({"global_init": {"track_positioning": {"enabled": true}}})";
  const std::string args = " init --tracks " + (dir_ / "scene" / "input").string() + " --config " + config.string();
  const fs::path one = dir_ / "i", two = dir_ / "init_into_a_much_longer_folder_name_for_another_heap_layout";
  pgba::test::CliResult r = Run("--threads 1" + args + " --out " + one.string());
  ASSERT_EQ(r.code, 0) << r.output;
  r = Run("--threads 2" + args + " --out " + two.string());
  ASSERT_EQ(r.code, 0) << r.output;
  for (const char* f : {"init/images.txt", "init/points3D.txt", "triplets.json"}) {
    ASSERT_TRUE(fs::exists(one / f)) << f;
    EXPECT_TRUE(Bytes(one / f) == Bytes(two / f)) << f << " differs between 1 and 2 threads";
  }
}

// The whole mission on photographs: features (OpenCV's SIFT runs its own parallel loops),
// matching and verification (one pair per task), tracks, and the reconstruction give the same
// bytes with 1 and 2 threads. The same workspace then serves two hostile re-runs: a failed one
// leaves no stale result, and a FIFO where the tracks key was is refused instead of blocking.
TEST_F(DeterminismCli, RunOnPhotosIsByteIdenticalForOneAndTwoThreads) {
  const fs::path scene = dir_ / "photos";
  ASSERT_EQ(Run("synth --render --images 12 --width 400 --height 300 --seed 2 --out " + scene.string()).code, 0);
  const std::string images = " --images " + (scene / "images").string() + " --calib " + (scene / "cameras.txt").string();
  const fs::path one = dir_ / "run1", two = dir_ / "run2_in_a_folder_of_another_name_length";
  pgba::test::CliResult r = Run("--threads 1 run" + images + " --out " + one.string());
  ASSERT_EQ(r.code, 0) << r.output;
  r = Run("--threads 2 run" + images + " --out " + two.string());
  ASSERT_EQ(r.code, 0) << r.output;
  std::vector<fs::path> files;  // every file of the workspace but the timed reports and the log
  for (const auto& e : fs::recursive_directory_iterator(one))
    if (e.is_regular_file()) files.push_back(fs::relative(e.path(), one));
  std::sort(files.begin(), files.end());
  for (const char* f : {"sparse/images.txt", "sparse/points3D.txt", "points.ply", "tracks/images.txt",
                        "features/images.json", "triplets.json", "local_hessians.json"})
    EXPECT_TRUE(std::find(files.begin(), files.end(), fs::path(f)) != files.end()) << f;
  for (const fs::path& f : files) {
    if (f == "report.json" || f == "report.html" || f == "log.txt") continue;
    EXPECT_TRUE(Bytes(one / f) == Bytes(two / f)) << f << " differs between 1 and 2 threads";
  }
  // report.html holds the stages' timings; the data of its 3D view is the model's, the same.
  const auto view_data = [](const std::string& html) {
    const std::string start = "id=\"pgba-view3d-data\">";
    const size_t from = html.find(start);
    return from == std::string::npos ? std::string() : html.substr(from, html.find("</script>", from) - from);
  };
  const std::string view_one = view_data(Bytes(one / "report.html"));
  EXPECT_NE(view_one.find("\"cameras\""), std::string::npos);
  EXPECT_TRUE(view_one == view_data(Bytes(two / "report.html"))) << "the 3D view differs between 1 and 2 threads";

  // A failed re-run (every pair rejected) leaves nothing that reads as a result.
  const fs::path impossible = dir_ / "impossible.json";
  std::ofstream(impossible) << R"({"pairs": {"min_inliers": 100000}})";
  r = Run("run" + images + " --out " + one.string() + " --config " + impossible.string());
  EXPECT_EQ(r.code, 2) << r.output;
  for (const char* f : {"sparse", "points.ply", "report.html", "fingerprint.json"})
    EXPECT_FALSE(fs::exists(one / f)) << f << " left by the failed re-run";
  std::ifstream report(one / "report.json");
  EXPECT_NE(std::string(std::istreambuf_iterator<char>(report), {}).find("\"failed\""), std::string::npos);

  // A FIFO as the tracks key: refused, naming it (reading it blocked the run for ever).
  const fs::path key = one / "tracks" / "key.json";
  ASSERT_TRUE(fs::remove(key));
  ASSERT_EQ(::mkfifo(key.c_str(), 0600), 0);
  r = pgba::test::RunPgbaWithin(120, "-v 0 run" + images + " --out " + one.string());
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_EQ(r.output, "error: " + key.string() + ": is not a regular file (FIFO, socket or device), refusing to read it\n");

  // A FIFO as the log: refused before any work (opening it for writing blocked).
  const fs::path log = one / "log.txt";
  ASSERT_TRUE(fs::remove(log));
  ASSERT_EQ(::mkfifo(log.c_str(), 0600), 0);
  r = pgba::test::RunPgbaWithin(120, "-v 0 run" + images + " --out " + one.string());
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_EQ(r.output, "error: " + log.string() + ": is not a regular file (device, FIFO or socket), refusing to replace it\n");
}

TEST_F(DeterminismCli, ThreadsOptionIsValidated) {
  const pgba::test::CliResult r = Run("--threads -3 synth --scenario orbit --out " + (dir_ / "x").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("--threads"), std::string::npos) << r.output;
}

}  // namespace
