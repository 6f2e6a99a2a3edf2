// Hostile usage: every error is one line naming the file (or the option) and the problem,
// never a library's raw text.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "tests/apps/hostile_cli_fixture.h"

namespace {
namespace fs = std::filesystem;
using pgba::test::Bytes;
using pgba::test::Lines;

class HostileMessagesCli : public pgba::test::HostileCli {};

// Unclear errors: an unknown subcommand is named, with the known ones.
TEST_F(HostileMessagesCli, UnknownSubcommandIsNamed) {
  const pgba::test::CliResult r = Run("reconstrct --tracks x --out y");
  ExpectOneLineError(r, "reconstrct", "unknown command 'reconstrct'");
}

// Unclear errors: std::bad_alloc, a raw filesystem error, a calibration that ended as "no
// verified matches", a config key reported as a flag after the features stage, a global
// option placed after the command.
TEST_F(HostileMessagesCli, ErrorsNameTheFileAndTheProblem) {
  ExpectOneLineError(Run("synth --scenario orbit --points 2000000000 --out " + (dir_ / "huge").string()), "--points",
                     "must be <= ");
  const fs::path file = dir_ / "a_file";
  std::ofstream(file) << "x";
  ExpectOneLineError(Run("synth --scenario orbit --images 20 --points 500 --out " + (file / "x").string()),
                     (file / "x").string(), "Not a directory");

  const fs::path images = Photos("bad_calib");
  for (const std::string& line : {std::string("1 PINHOLE 320 240 1e-9 1e-9 160 120"),
                                  std::string("1 PINHOLE 320 240 1e300 1e300 160 120")}) {
    const fs::path calib = dir_ / "bad_calib" / "focal.txt";
    std::ofstream(calib, std::ios::trunc) << line << "\n";
    ExpectOneLineError(Run("features --images " + images.string() + " --calib " + calib.string() + " --out " +
                           (dir_ / "bad_calib_ws").string()),
                       calib.string() + ":1", "is implausible for a 320x240 image");
  }
  const fs::path calib = dir_ / "bad_calib" / "principal.txt";
  std::ofstream(calib) << "1 PINHOLE 320 240 300 300 900 120\n";
  ExpectOneLineError(Run("features --images " + images.string() + " --calib " + calib.string() + " --out " +
                         (dir_ / "bad_calib_ws").string()),
                     calib.string() + ":1", "principal point (900, 120) is outside the 320x240 image");

  const fs::path config = dir_ / "bad_pairs.json";
  std::ofstream(config) << R"({"matching": {"pairs": {"method": "bogus"}}})";
  ExpectOneLineError(Run("run --images " + images.string() + " --out " + (dir_ / "bad_pairs_out").string() +
                         " --config " + config.string()),
                     config.string(), "matching.pairs.method");
  EXPECT_FALSE(fs::exists(dir_ / "bad_pairs_out" / "features"));

  ExpectOneLineError(Run("features --images " + images.string() + " --out " + (dir_ / "threads_ws").string() +
                         " --threads 1"),
                     "--threads", "a global option, placed before the command");
}

// A usage error is one line (not CLI11's message followed by a hint to run --help): the
// problem first and where the usage is after it, for every command.
TEST_F(HostileMessagesCli, UsageErrorsAreOneLine) {
  struct Case {
    std::string args, problem, hint;
  };
  const std::vector<Case> cases = {
      {"init --no-such-flag --out x", "--no-such-flag", "(usage: pgba init --help)"},
      {"synth --images abc --out x", "--images = abc", "(usage: pgba synth --help)"},
      {"features", "--images is required", "(usage: pgba features --help)"},
      {"match --out x --window 1.5", "--window", "(usage: pgba match --help)"},
      {"evaluate", "MODEL is required", "(usage: pgba evaluate --help)"},
      {"reconstruct --tracks x", "--out is required", "(usage: pgba reconstruct --help)"},
      {"benchmark --tracks x --out y --perturb-deg nan", "--perturb-deg", "(usage: pgba benchmark --help)"},
      {"run --images x --out y --calib-prior=maybe", "--calib-prior", "(usage: pgba run --help)"},
      {"convert tanks --log x", "required", "(usage: pgba convert --help)"},
      {"", "A subcommand is required", "(usage: pgba --help)"},
  };
  for (const Case& c : cases) {
    const pgba::test::CliResult r = Run(c.args);
    EXPECT_EQ(r.code, 2) << c.args << ": " << r.output;
    const std::vector<std::string> lines = Lines(r.output);
    ASSERT_EQ(lines.size(), 1u) << c.args << ": " << r.output;
    EXPECT_EQ(lines[0].rfind("error: ", 0), 0u) << lines[0];
    EXPECT_NE(lines[0].find(c.problem), std::string::npos) << lines[0];
    ASSERT_GE(lines[0].size(), c.hint.size());
    EXPECT_EQ(lines[0].substr(lines[0].size() - c.hint.size()), c.hint) << lines[0];
  }
}

// A line break in a path the user gave split the error in two: control characters of a
// message are shown escaped.
TEST_F(HostileMessagesCli, ALineBreakInAPathStaysOnTheErrorLine) {
  const pgba::test::CliResult r =
      Run("features --images \"$(printf '" + (dir_ / "no\\nsuch").string() + "')\" --out " + (dir_ / "nl_ws").string());
  ExpectOneLineError(r, (dir_ / "no\\x0asuch").string(), "image folder not found");
  EXPECT_FALSE(fs::exists(dir_ / "nl_ws" / "features"));
}

// A stage's finding about the tracks ("tracks: no image pair could be verified (too few
// shared tracks?)") names the tracks model's images.txt, in the error line and in
// report.json, for every command that reconstructs from a tracks model.
TEST_F(HostileMessagesCli, AStagesFindingAboutTheTracksNamesTheTracksFile) {
  const fs::path sparse = dir_ / "sparse_scene";
  ASSERT_EQ(Run("synth --scenario orbit --images 20 --points 500 --out " + sparse.string()).code, 0);
  const std::string tracks = (sparse / "input").string(), images_txt = (sparse / "input" / "images.txt").string();
  for (const std::string& command : {std::string("init"), std::string("reconstruct"), std::string("benchmark")}) {
    const fs::path out = dir_ / ("sparse_" + command);
    ExpectOneLineError(Run(command + " --tracks " + tracks + " --out " + out.string()), images_txt + ": ",
                       "no image pair could be verified");
    if (command != "benchmark") {
      EXPECT_NE(Bytes(out / "report.json").find("\"error\": \"" + images_txt + ": no image pair"), std::string::npos)
          << command << ": " << Bytes(out / "report.json");
    }
  }
}

}  // namespace
