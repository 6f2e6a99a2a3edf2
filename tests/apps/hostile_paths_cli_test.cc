// Hostile paths and outputs: FIFOs, symbolic links and loops, truncated files, outputs that
// are, contain or lie inside an input, empty output paths, and failed re-runs: an output is
// never half-written and a failed run leaves nothing that reads as its result.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "tests/apps/hostile_cli_fixture.h"

namespace {
namespace fs = std::filesystem;
using pgba::test::Bytes;
using pgba::test::Lines;

class HostilePathsCli : public pgba::test::HostileCli {};

// Hang: a FIFO named images.txt beside a valid cameras.txt and points3D.txt.
TEST_F(HostilePathsCli, FifoImagesTxt) {
  const fs::path model = ModelCopy("fifo_model");
  fs::remove(model / "images.txt");
  ASSERT_EQ(::mkfifo((model / "images.txt").c_str(), 0600), 0);
  const fs::path out = dir_ / "fifo_out";
  ExpectOneLineError(Run("reconstruct --tracks " + model.string() + " --out " + out.string()),
                     (model / "images.txt").string(), "is not a regular file");
  ExpectOneLineError(Run("init --tracks " + model.string() + " --out " + out.string()),
                     (model / "images.txt").string(), "is not a regular file");
  EXPECT_FALSE(fs::exists(out / "sparse"));
}

// As root, --json /dev/full (or a symlink) was replaced by a regular file. A FIFO stands for
// the device here (the same refusal; tests/util/atomic_file_test.cc tries /dev/full itself),
// refused before the evaluation runs.
TEST_F(HostilePathsCli, JsonOutputOntoFifoIsRefusedAndSymlinkFollowed) {
  const std::string eval = "evaluate " + (dir_ / "scene" / "gt").string() + " --obs " +
                           (dir_ / "scene" / "input").string() + " --json ";
  const fs::path fifo = dir_ / "metrics.fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  ExpectOneLineError(Run(eval + fifo.string()), fifo.string(), "not a regular file");
  EXPECT_TRUE(fs::is_fifo(fs::symlink_status(fifo)));
  const fs::path target = dir_ / "metrics_target.json", link = dir_ / "metrics_link.json";
  std::ofstream(target) << "{}";
  fs::create_symlink(target, link);
  const pgba::test::CliResult r = Run(eval + link.string());
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(fs::is_symlink(fs::symlink_status(link)));
  EXPECT_NE(Bytes(target).find("sigma_rms"), std::string::npos);
}

// Unclear errors: a truncated JPEG (libjpeg only said "Premature end of JPEG file") and a
// symlink loop in the image folder (a raw filesystem error aborted the run) are skipped
// with a warning naming each.
TEST_F(HostilePathsCli, TruncatedJpegAndSymlinkLoopAreSkippedWithAWarning) {
  const fs::path images = Photos("odd_images");
  const std::string whole = Bytes(images / "im2.jpg");
  std::ofstream(images / "cut.jpg", std::ios::binary) << whole.substr(0, whole.size() / 2);
  fs::create_symlink(images / "loop_b.jpg", images / "loop_a.jpg");
  fs::create_symlink(images / "loop_a.jpg", images / "loop_b.jpg");
  const pgba::test::CliResult r =
      Run("features --images " + images.string() + " --out " + (dir_ / "odd_ws").string());
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find((images / "cut.jpg").string() + ": truncated JPEG"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find((images / "loop_a.jpg").string() + ": cannot access"), std::string::npos) << r.output;
  for (const std::string& line : Lines(r.output)) EXPECT_EQ(line.rfind("warning: ", 0), 0u) << line;
  EXPECT_TRUE(fs::exists(dir_ / "odd_ws" / "features" / "im0.jpg.bin"));
  EXPECT_FALSE(fs::exists(dir_ / "odd_ws" / "features" / "cut.jpg.bin"));
}

// Data loss: converting a dataset into its own folder replaced every photo by a symbolic link
// to itself (exit 0). An output that is, contains or lies inside an input is refused before
// anything is touched.
TEST_F(HostilePathsCli, ConvertIntoTheDatasetItselfLeavesThePhotosUntouched) {
  const fs::path images = Photos("own_ds"), ds = images.parent_path();
  const fs::path log = dir_ / "own_ds.log";
  {
    std::ofstream out(log);
    for (int i = 0; i < 3; ++i) out << i << " " << i << " 0\n1 0 0 " << i << "\n0 1 0 0\n0 0 1 0\n0 0 0 1\n";
  }
  std::vector<std::string> before;
  for (int i = 0; i < 3; ++i) before.push_back(Bytes(images / ("im" + std::to_string(i) + ".jpg")));
  const std::string args = "convert tanks --log " + log.string() + " --images " + images.string() + " --cameras " +
                           (ds / "cameras.txt").string() + " --out ";
  ExpectOneLineError(Run(args + ds.string()), ds.string(), "would replace the input --images");
  ExpectOneLineError(Run(args + (ds / "." / "").string()), ds.string(), "the input --images");
  ExpectOneLineError(Run(args + (images / "converted").string()), (images / "converted").string(),
                     "lies inside the input --images");
  ExpectOneLineError(Run(args + images.string()), images.string(), "is the input --images");
  for (int i = 0; i < 3; ++i) {
    const fs::path photo = images / ("im" + std::to_string(i) + ".jpg");
    EXPECT_FALSE(fs::is_symlink(fs::symlink_status(photo))) << photo;
    EXPECT_EQ(Bytes(photo), before[i]) << photo;
  }
  EXPECT_FALSE(fs::exists(images / "converted"));
  // The same rule for every command that writes: run into the photo folder, features with
  // --images under the output's features/, evaluate --json over an input file.
  ExpectOneLineError(Run("run --images " + images.string() + " --out " + images.string()), images.string(),
                     "is the input --images");
  ExpectOneLineError(Run("features --images " + images.string() + " --out " + (images / "ws").string()),
                     (images / "ws").string(), "lies inside the input --images");
  const fs::path model = ModelCopy("json_over_input");
  ExpectOneLineError(Run("evaluate " + model.string() + " --obs " + model.string() + " --json " +
                         (model / "images.txt").string()),
                     (model / "images.txt").string(), "lies inside the input MODEL");
  EXPECT_NE(Bytes(model / "images.txt").find("# Image list"), std::string::npos);
  // A workspace's own photo folder inside the output is fine: run writes no images/.
  const fs::path reconstruct_ws = dir_ / "own_ds_ws";
  ExpectOneLineError(Run("reconstruct --tracks " + (reconstruct_ws / "sparse").string() + " --out " +
                         reconstruct_ws.string()),
                     reconstruct_ws.string(), "would replace the input --tracks");
}

// An empty --out wrote into the current folder.
TEST_F(HostilePathsCli, EmptyOutIsAnError) {
  const fs::path images = Photos("empty_out");
  ExpectOneLineError(Run("features --images " + images.string() + " --out ''"), "--out", "is empty");
  ExpectOneLineError(Run("synth --scenario orbit --out ''"), "--out", "is empty");
}

// Stale outputs: a failed re-run of match or features left the earlier tracks/ or
// features/images.json, and a reconstruct refused at its options the earlier report.json
// with status ok; staging left by a killed process stayed forever.
TEST_F(HostilePathsCli, FailedReRunsLeaveNothingThatReadsAsTheirResult) {
  const fs::path images = Photos("stale_src"), ws = dir_ / "stale_ws";
  ASSERT_EQ(Run("features --images " + images.string() + " --out " + ws.string()).code, 0);
  ASSERT_TRUE(fs::exists(ws / "features" / "images.json"));
  const fs::path empty = dir_ / "stale_empty";
  fs::create_directories(empty);
  EXPECT_EQ(Run("features --images " + empty.string() + " --out " + ws.string()).code, 2);
  EXPECT_FALSE(fs::exists(ws / "features" / "images.json"));
  EXPECT_EQ(Bytes(ws / "report.json").find("\"features\""), std::string::npos) << Bytes(ws / "report.json");

  fs::create_directories(ws / "tracks");
  std::ofstream(ws / "tracks" / "points3D.txt") << "# an earlier result\n";
  EXPECT_EQ(Run("match --out " + ws.string()).code, 2);  // no feature index any more
  EXPECT_FALSE(fs::exists(ws / "tracks"));

  const fs::path out = dir_ / "stale_reconstruct";
  fs::create_directories(out / "sparse");
  std::ofstream(out / "report.json") << "{\"status\": \"ok\"}\n";
  // Staging of a process that is gone (pid 2^22 + 1 is above the kernel's pid_max default).
  fs::create_directories(out / "sparse.tmp.4194305.0");
  std::ofstream(out / "report.json.tmp.4194305.3") << "partial";
  const fs::path config = dir_ / "stale_config.json";
  std::ofstream(config) << R"({"local_hessian": {"huber_px": -1}})";
  EXPECT_EQ(Run("reconstruct --tracks " + (dir_ / "scene" / "input").string() + " --out " + out.string() +
                " --config " + config.string())
                .code,
            2);
  EXPECT_FALSE(fs::exists(out / "report.json"));
  EXPECT_FALSE(fs::exists(out / "sparse"));
  std::ofstream(config, std::ios::trunc) << "{}";
  // The next run that gets going clears the dead process' staging.
  Run("init --tracks " + (dir_ / "scene" / "input").string() + " --out " + out.string());
  EXPECT_FALSE(fs::exists(out / "sparse.tmp.4194305.0"));
  EXPECT_FALSE(fs::exists(out / "report.json.tmp.4194305.3"));
}

}  // namespace
