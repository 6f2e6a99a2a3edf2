// Hostile paths and outputs: FIFOs, symbolic links and loops, truncated files, outputs that
// are, contain or lie inside an input, empty output paths, and failed re-runs: an output is
// never half-written and a failed run leaves nothing that reads as its result.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "tests/apps/hostile_cli_fixture.h"
#include "tests/support/colmap_database_writer.h"

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

// Stale outputs: a failed re-run of match or features leaves no earlier tracks/ or
// features/images.json, a reconstruct refused at its options no earlier report.json with
// status ok, and the staging left by a killed process is removed by the next run.
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

// A full disk while a command writes: every write of the chosen file fails with ENOSPC
// (tests/support/full_disk.cc, preloaded). Exit code 2, one line naming the file and the
// cause, and nothing left that reads as the command's result (run's report.html, written last
// but one, left sparse/, points.ply and a report.json with status ok).
TEST_F(HostilePathsCli, AFullDiskEndsInOneLineNamingTheFileAndLeavesNoResult) {
  const fs::path scene = dir_ / "full_scene";
  ASSERT_EQ(Run("synth --render --images 10 --width 320 --height 240 --seed 2 --out " + scene.string()).code, 0);
  const std::string images = (scene / "images").string(), tracks = (dir_ / "scene" / "input").string();
  const std::string gt = (dir_ / "scene" / "gt").string();
  const fs::path features_ws = dir_ / "full_features";
  ASSERT_EQ(Run("features --images " + images + " --out " + features_ws.string()).code, 0);
  struct Case {
    std::string args, full;            // the command; the file the disk refuses (a path fragment)
    fs::path out;                      // its output
    std::vector<std::string> results;  // what would read as its result
  };
  const fs::path o = dir_ / "full_out";
  const std::vector<Case> cases = {
      {"run --images " + images + " --out " + o.string(), "report.html", o, {"sparse", "points.ply", "report.html"}},
      {"run --images " + images + " --out " + o.string(), "report.json", o, {"sparse", "points.ply", "report.html"}},
      {"reconstruct --tracks " + tracks + " --out " + o.string(), "points.ply", o, {"sparse", "points.ply"}},
      {"init --tracks " + tracks + " --out " + o.string(), "report.json", o, {"fingerprint.json"}},
      {"benchmark --tracks " + tracks + " --out " + o.string(), "convergence.svg", o,
       {"benchmark.json", "models", "convergence.svg"}},
      {"synth --scenario aerial --images 12 --out " + o.string(), "points3D.txt", o, {"gt", "input"}},
      {"features --images " + images + " --out " + o.string(), "images.json", o, {"features/images.json"}},
      {"match --out " + features_ws.string(), "two_view_geometries.txt", features_ws, {"tracks"}},
      {"evaluate " + gt + " --obs " + tracks + " --json " + (o / "metrics.json").string(), "metrics.json", o,
       {"metrics.json"}},
  };
  for (const Case& c : cases) {
    fs::remove_all(o);
    const pgba::test::CliResult r = pgba::test::RunCommand(
        "PGBA_FULL_DISK=" + c.full + " LD_PRELOAD=" + PGBA_FULL_DISK_LIBRARY +
        " ASAN_OPTIONS=\"$ASAN_OPTIONS:verify_asan_link_order=0\" timeout --kill-after=5 " +
        std::to_string(kTimeoutSeconds) + " " + PGBA_BINARY + " -v 0 " + c.args + " 2>&1");
    EXPECT_EQ(r.code, 2) << c.args << ": " << r.output;
    const std::vector<std::string> lines = Lines(r.output);
    ASSERT_EQ(lines.size(), 1u) << c.args << ": " << r.output;
    const std::string cause = ": cannot write: No space left on device";
    EXPECT_EQ(lines[0].rfind("error: " + c.out.string(), 0), 0u) << lines[0];
    EXPECT_NE(lines[0].find(c.full), std::string::npos) << lines[0];
    ASSERT_GT(lines[0].size(), cause.size());
    EXPECT_EQ(lines[0].substr(lines[0].size() - cause.size()), cause) << lines[0];
    for (const std::string& result : c.results) EXPECT_FALSE(fs::exists(c.out / result)) << c.args << ": " << result;
    EXPECT_EQ(Bytes(c.out / "report.json").find("\"status\": \"ok\""), std::string::npos) << c.args;
    // Nothing half-written under a temporary name either.
    if (fs::exists(c.out))
      for (const auto& e : fs::recursive_directory_iterator(c.out))
        EXPECT_EQ(e.path().filename().string().find(".tmp."), std::string::npos) << c.args << ": " << e.path();
  }
}

// Every file below `path` (or `path` itself) with its bytes: an input is untouched when its
// snapshot is the same after the command.
std::map<std::string, std::string> Snapshot(const fs::path& path) {
  std::map<std::string, std::string> files;
  if (fs::is_regular_file(path)) files[path.string()] = Bytes(path);
  if (fs::is_directory(path))
    for (const auto& e : fs::recursive_directory_iterator(path))
      if (e.is_regular_file()) files[e.path().string()] = Bytes(e.path());
  return files;
}

// Outputs apart from inputs, for every command that writes: an output that is an input, lies
// inside an input folder, or would replace an entry of the output that holds an input is
// refused before anything is touched (exit 2, one line naming the output and the input), and
// the input is left as it was.
TEST_F(HostilePathsCli, EveryWritingCommandKeepsItsOutputApartFromItsInputs) {
  const fs::path tracks = ModelCopy("apart_tracks"), photos = Photos("apart_photos");
  const fs::path gt = ModelCopy("apart_gt"), config = dir_ / "apart_config.json", loop = dir_ / "apart_loop.txt";
  const fs::path gcp = dir_ / "apart_gcp.txt", db = dir_ / "apart.db";
  std::ofstream(config) << "{}";
  std::ofstream(loop) << "a.jpg 1 2 b.jpg 3 4\n";
  std::ofstream(gcp) << "GCP g 1 2 3\n";
  {
    pgba::test::DbWriter w(db.string());
    w.Camera(1, 1, 100, 100, {90, 90, 50, 50});
    w.Image(1, "a.jpg", 1);
  }
  // An input placed at `entry` of a fresh output folder `name`, which the command writes.
  auto inside_output = [&](const std::string& name, const std::string& entry, const fs::path& input) {
    const fs::path out = dir_ / name, at = out / entry;
    fs::remove_all(out);
    fs::create_directories(at.parent_path());
    fs::copy(input, at, fs::copy_options::recursive);
    return std::make_pair(out, at);
  };
  const auto [features_ws, features_images] = inside_output("apart_features_ws", "features/images", photos);
  const auto [match_ws, match_db] = inside_output("apart_match_ws", "tracks/db.db", db);
  const auto [init_ws, init_tracks] = inside_output("apart_init_ws", "init", tracks);
  const auto [reconstruct_ws, reconstruct_gcp] = inside_output("apart_reconstruct_ws", "points.ply", gcp);
  const auto [run_ws, run_images] = inside_output("apart_run_ws", "features", photos);
  const auto [benchmark_ws, benchmark_loop] = inside_output("apart_benchmark_ws", "benchmark.json", loop);
  const auto [benchmark_ws2, benchmark_tracks] = inside_output("apart_benchmark_ws2", "models/x", tracks);
  struct Case {
    std::string args;
    fs::path out, input;  // the output the command is given, the input it must leave as it was
    std::string problem;
  };
  const std::string t = " --tracks " + tracks.string();
  const std::vector<Case> cases = {
      {"features --images " + photos.string() + " --out ", photos, photos, "is the input --images"},
      {"features --images " + photos.string() + " --out ", photos / "ws", photos, "lies inside the input --images"},
      {"features --images " + features_images.string() + " --out ", features_ws, features_images,
       "would replace the input --images"},
      {"match --database " + db.string() + " --out ", db, db, "is the input --database"},
      {"match --database " + match_db.string() + " --out ", match_ws, match_db, "would replace the input --database"},
      {"init" + t + " --out ", tracks, tracks, "is the input --tracks"},
      {"init" + t + " --out ", tracks / "ws", tracks, "lies inside the input --tracks"},
      {"init --tracks " + init_tracks.string() + " --out ", init_ws, init_tracks, "would replace the input --tracks"},
      {"init --database " + db.string() + " --out ", db, db, "is the input --database"},
      {"init" + t + " --config " + config.string() + " --out ", config, config, "is the input --config"},
      {"reconstruct" + t + " --out ", tracks / "out", tracks, "lies inside the input --tracks"},
      {"reconstruct" + t + " --gcp " + reconstruct_gcp.string() + " --out ", reconstruct_ws, reconstruct_gcp,
       "would replace the input --gcp"},
      {"reconstruct" + t + " --workspace " + tracks.string() + " --out ", tracks, tracks, "is the input --tracks"},
      {"run --images " + photos.string() + " --out ", photos / "out", photos, "lies inside the input --images"},
      {"run --images " + run_images.string() + " --out ", run_ws, run_images, "would replace the input --images"},
      {"run --images " + photos.string() + " --gt " + gt.string() + " --out ", gt, gt, "is the input --gt"},
      {"benchmark" + t + " --out ", tracks, tracks, "is the input --tracks"},
      {"benchmark --tracks " + benchmark_tracks.string() + " --out ", benchmark_ws2, benchmark_tracks,
       "would replace the input --tracks"},
      {"benchmark" + t + " --gt " + gt.string() + " --out ", gt / "b", gt, "lies inside the input --gt"},
      {"benchmark" + t + " --loop " + benchmark_loop.string() + " --out ", benchmark_ws, benchmark_loop,
       "would replace the input --loop"},
      {"evaluate " + gt.string() + " --obs " + tracks.string() + " --json ", tracks, tracks, "is the input --obs"},
      {"evaluate " + gt.string() + " --obs " + tracks.string() + " --json ", gt / "m.json", gt,
       "lies inside the input MODEL"},
      {"convert eth3d-slam --sequence " + tracks.string() + " --out ", tracks / "ds", tracks,
       "lies inside the input --sequence"},
  };
  for (const Case& c : cases) {
    const std::map<std::string, std::string> before = Snapshot(c.input);
    ASSERT_FALSE(before.empty()) << c.input;
    const bool existed = fs::exists(c.out);
    ExpectOneLineError(Run(c.args + c.out.string()), c.out.string() + ": ", c.problem);
    EXPECT_TRUE(Snapshot(c.input) == before) << c.args << c.out.string() << " touched " << c.input;
    EXPECT_EQ(fs::exists(c.out), existed) << c.args << c.out.string();
  }
}

// An output below a regular file, for every command that writes: exit 2 and one line naming
// the output path, before any work (no raw "filesystem error: cannot create directories").
// (match reads its workspace first: there the feature index below the file is missing.)
TEST_F(HostilePathsCli, EveryWritingCommandRefusesAnOutputBelowAFile) {
  const fs::path file = dir_ / "below_file";
  std::ofstream(file) << "x";
  const fs::path out = file / "out";
  const std::string t = " --tracks " + (dir_ / "scene" / "input").string();
  const std::string photos = Photos("below_photos").string();
  const fs::path log = dir_ / "below_photos.log";
  {
    std::ofstream out(log);
    for (int i = 0; i < 3; ++i) out << i << " " << i << " 0\n1 0 0 " << i << "\n0 1 0 0\n0 0 1 0\n0 0 0 1\n";
  }
  const std::vector<std::string> commands = {
      "synth --scenario orbit --images 20 --points 500 --out " + out.string(),
      "features --images " + photos + " --out " + out.string(),
      "init" + t + " --out " + out.string(),
      "reconstruct" + t + " --out " + out.string(),
      "run --images " + photos + " --out " + out.string(),
      "benchmark" + t + " --out " + out.string(),
      "evaluate " + (dir_ / "scene" / "gt").string() + " --obs " + (dir_ / "scene" / "input").string() + " --json " +
          (out / "m.json").string(),
      "convert tanks --log " + log.string() + " --images " + photos + " --cameras " +
          (dir_ / "below_photos" / "cameras.txt").string() + " --out " + out.string(),
  };
  for (const std::string& args : commands) {
    const pgba::test::CliResult r = Run(args);
    ExpectOneLineError(r, out.string(), "");
    EXPECT_TRUE(r.output.find("Not a directory") != std::string::npos ||
                r.output.find("not a directory") != std::string::npos)
        << args << ": " << r.output;
    EXPECT_EQ(r.output.find("filesystem error"), std::string::npos) << r.output;
    EXPECT_EQ(Bytes(file), "x");
  }
}

// An input folder that is a symbolic link loop read as "not found", a file given as the photo
// folder as "image folder not found": each says what it is.
TEST_F(HostilePathsCli, InputFoldersThatAreNoFoldersSayWhatTheyAre) {
  const fs::path loop = dir_ / "folder_loop", file = dir_ / "folder_file";
  fs::create_symlink(dir_ / "folder_loop2", loop);
  fs::create_symlink(loop, dir_ / "folder_loop2");
  std::ofstream(file) << "x";
  const std::string out = " --out " + (dir_ / "folder_out").string();
  ExpectOneLineError(Run("init --tracks " + loop.string() + out), loop.string() + ": ",
                     "cannot access: Too many levels of symbolic links");
  ExpectOneLineError(Run("features --images " + loop.string() + out), loop.string() + ": ",
                     "cannot access: Too many levels of symbolic links");
  ExpectOneLineError(Run("features --images " + file.string() + out), file.string() + ": ",
                     "is not a directory (expected a folder of photos)");
  ExpectOneLineError(Run("evaluate " + file.string() + " --obs " + (dir_ / "scene" / "input").string()),
                     file.string() + ": ", "is not a directory (expected a COLMAP text model)");
  EXPECT_FALSE(fs::exists(dir_ / "folder_out" / "features"));
}

}  // namespace
