// `pgba reconstruct` end to end on a synthetic aerial block (0.5 px, 2% outlier
// observations): the final model is accurate against the truth and better than the initial
// one; `--workspace` re-runs the global BA from the stored motions and local hessians and
// gives the same poses; a foreign or incomplete workspace is an error naming the file.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "pgba/geometry/rotation.h"
#include "pgba/io/colmap_text.h"
#include "tests/apps/cli_runner.h"

namespace {
namespace fs = std::filesystem;

class ReconstructCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("pgba_reconstruct_cli_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    ASSERT_EQ(Run("synth --scenario aerial --images 24 --seed 3 --noise 0.5 --outliers 0.02 --out " +
                  (dir_ / "scene").string())
                  .code,
              0);
    ASSERT_EQ(Run("synth --scenario orbit --images 40 --seed 3 --out " + (dir_ / "other").string()).code, 0);
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }

  static pgba::test::CliResult Run(const std::string& args) { return pgba::test::RunPgba("-v 0 " + args); }

  static nlohmann::json Evaluate(const fs::path& model) {
    const fs::path json = dir_ / "eval.json";
    EXPECT_EQ(Run("evaluate " + model.string() + " --obs " + (dir_ / "scene" / "input").string() + " --gt " +
                  (dir_ / "scene" / "gt").string() + " --json " + json.string())
                  .code,
              0);
    std::ifstream in(json);
    return nlohmann::json::parse(in);
  }

  static fs::path dir_;
};
fs::path ReconstructCli::dir_;

TEST_F(ReconstructCli, AccurateModelAndWorkspaceReRunGivesTheSamePoses) {
  const fs::path out = dir_ / "out", again = dir_ / "again";
  const std::string tracks = " --tracks " + (dir_ / "scene" / "input").string();
  ASSERT_EQ(Run("reconstruct" + tracks + " --out " + out.string()).code, 0);
  for (const char* f : {"sparse/images.txt", "sparse/points3D.txt", "points.ply", "report.json", "triplets.json",
                        "motions.json", "local_hessians.json", "init/images.txt"})
    EXPECT_TRUE(fs::exists(out / f)) << f;
  const nlohmann::json init = Evaluate(out / "init"), final = Evaluate(out / "sparse");
  EXPECT_EQ(final["images_registered"], 24);
  EXPECT_LT(final["rot_err_deg_median"].get<double>(), 0.05);
  EXPECT_LT(final["center_err_rel_median"].get<double>(), 0.005);
  EXPECT_LT(final["sigma_rms"].get<double>(), 0.9 * init["sigma_rms"].get<double>());

  ASSERT_EQ(Run("reconstruct" + tracks + " --out " + again.string() + " --workspace " + out.string()).code, 0);
  // Same poses up to the text round trip of the stored artefacts: the motions, their models and
  // their points are read back (motions.json, local_hessians.json), so only the rotations
  // stored as quaternions (init/, local poses) differ from the first run's matrices in their
  // last bits (measured: 3e-11 deg, 3e-13 of the extent).
  const pgba::Reconstruction a = pgba::ReadColmapText((out / "sparse").string());
  const pgba::Reconstruction b = pgba::ReadColmapText((again / "sparse").string());
  ASSERT_EQ(a.images.size(), b.images.size());
  for (const auto& [id, im] : a.images) {
    EXPECT_LT((im.pose.C() - b.images.at(id).pose.C()).norm(), 1e-11 * 1000.0) << im.name;  // ~1 km
    EXPECT_LT(pgba::RotationAngleDeg(im.pose.R(), b.images.at(id).pose.R()), 1e-9) << im.name;
  }
  std::ifstream in(again / "report.json");
  const nlohmann::json report = nlohmann::json::parse(in);
  EXPECT_TRUE(report["stages"]["local_hessians"].contains("read_from"));
  EXPECT_FALSE(report["stages"].contains("triplets"));  // the initialisation was not re-run
}

TEST_F(ReconstructCli, ForeignOrIncompleteWorkspaceIsAnErrorNamingTheFile) {
  const fs::path ws = dir_ / "ws_other";
  ASSERT_EQ(Run("init --tracks " + (dir_ / "other" / "input").string() + " --out " + ws.string()).code, 0);
  const std::string tracks = " --tracks " + (dir_ / "scene" / "input").string();
  pgba::test::CliResult r = Run("reconstruct" + tracks + " --out " + (dir_ / "x").string() + " --workspace " + ws.string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find((ws / "fingerprint.json").string() + ": the workspace was computed from other tracks"),
            std::string::npos)
      << r.output;
  // A workspace of these tracks with an artefact missing.
  const fs::path same = dir_ / "ws_same";
  ASSERT_EQ(Run("init" + tracks + " --out " + same.string()).code, 0);
  fs::remove(same / "triplets.json");
  r = Run("reconstruct" + tracks + " --out " + (dir_ / "x").string() + " --workspace " + same.string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("triplets.json: missing"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir_ / "x" / "sparse"));
}

// The workspace of another scene whose images have the same names (without a check: exit 0,
// 4 of 70 images, 22 degrees). The fingerprint of the inputs refuses it, and so it does a
// workspace initialised with other options or without a fingerprint.
TEST_F(ReconstructCli, WorkspaceOfOtherSceneSameNamesOrOtherOptionsIsRefused) {
  const fs::path twin = dir_ / "twin";
  ASSERT_EQ(Run("synth --scenario aerial --images 24 --seed 4 --noise 0.5 --out " + twin.string()).code, 0);
  const fs::path ws = dir_ / "ws_twin";
  ASSERT_EQ(Run("init --tracks " + (twin / "input").string() + " --out " + ws.string()).code, 0);
  const std::string tracks = " --tracks " + (dir_ / "scene" / "input").string();
  const fs::path out = dir_ / "twin_out";
  pgba::test::CliResult r = Run("reconstruct" + tracks + " --out " + out.string() + " --workspace " + ws.string());
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("computed from other tracks"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(out / "sparse"));

  const fs::path mine = dir_ / "ws_mine";
  ASSERT_EQ(Run("init" + tracks + " --out " + mine.string()).code, 0);
  const fs::path config = dir_ / "other_options.json";
  std::ofstream(config) << R"({"triplets": {"max_triplets_per_image": 3}})";
  r = Run("reconstruct" + tracks + " --out " + out.string() + " --workspace " + mine.string() + " --config " +
          config.string());
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("initialised with other options (triplets.max_triplets_per_image: 6 there, 3 here)"),
            std::string::npos)
      << r.output;
  fs::remove(mine / "fingerprint.json");
  r = Run("reconstruct" + tracks + " --out " + out.string() + " --workspace " + mine.string());
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find((mine / "fingerprint.json").string() + ": missing"), std::string::npos) << r.output;
}

// A failed re-run into the same --out leaves nothing of the earlier success that reads as
// its result: no sparse/, no points.ply, and a report.json that says "failed".
TEST_F(ReconstructCli, FailedReRunLeavesNoStaleResult) {
  const fs::path out = dir_ / "rerun";
  const std::string tracks = " --tracks " + (dir_ / "scene" / "input").string();
  ASSERT_EQ(Run("reconstruct" + tracks + " --out " + out.string()).code, 0);
  {
    std::ifstream in(out / "report.json");
    EXPECT_EQ(nlohmann::json::parse(in)["status"], "ok");
  }
  // Every pair rejected: no reconstruction is possible.
  const fs::path config = dir_ / "impossible.json";
  std::ofstream(config) << R"({"pairs": {"min_inliers": 100000}})";
  const pgba::test::CliResult r = Run("reconstruct" + tracks + " --out " + out.string() + " --config " + config.string());
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_FALSE(fs::exists(out / "sparse"));
  EXPECT_FALSE(fs::exists(out / "points.ply"));
  EXPECT_FALSE(fs::exists(out / "fingerprint.json"));
  std::ifstream in(out / "report.json");
  const nlohmann::json report = nlohmann::json::parse(in);
  EXPECT_EQ(report["status"], "failed");
  EXPECT_FALSE(report["error"].get<std::string>().empty());
}

// A bad --out is found before the computation, not after it.
TEST_F(ReconstructCli, BadOutIsAnErrorBeforeAnyWork) {
  const fs::path file = dir_ / "a_file";
  std::ofstream(file) << "x";
  const pgba::test::CliResult r =
      Run("reconstruct --tracks " + (dir_ / "scene" / "input").string() + " --out " + (file / "sub").string());
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find((file / "sub").string() + ": cannot create the output folder"), std::string::npos)
      << r.output;
  EXPECT_EQ(r.output.find("pairs"), std::string::npos) << r.output;  // no stage ran
}

}  // namespace

// Every command reads a configs/ preset through the one loader (run_pipeline.h): `init`
// accepts a preset with sections of stages it does not run (matching, ...) and still names
// an unknown section.
namespace {
TEST_F(ReconstructCli, InitAcceptsEveryPresetAndRejectsUnknownSections) {
  for (const auto& entry : fs::directory_iterator(fs::path(PGBA_SOURCE_DIR) / "configs")) {
    const fs::path ws = dir_ / ("init_" + entry.path().stem().string());
    const pgba::test::CliResult r = Run("init --tracks " + (dir_ / "scene" / "input").string() + " --out " +
                                        ws.string() + " --config " + entry.path().string());
    EXPECT_EQ(r.code, 0) << entry.path() << "\n" << r.output;
    EXPECT_TRUE(fs::exists(ws / "init" / "images.txt")) << entry.path();
  }
  const fs::path bogus = dir_ / "bogus.json";
  std::ofstream(bogus) << R"({"bogus": {}})";
  const pgba::test::CliResult r = Run("init --tracks " + (dir_ / "scene" / "input").string() + " --out " +
                                      (dir_ / "init_bogus").string() + " --config " + bogus.string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find(bogus.string() + ": unknown section 'bogus'"), std::string::npos) << r.output;
}
}  // namespace
