// `pgba reconstruct` end to end on a synthetic aerial block (0.5 px, 2% outlier
// observations): the final model is accurate against the truth and better than the initial
// one; `--workspace` re-runs the global BA from the stored triplets and local hessians and
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
                        "local_hessians.json", "init/images.txt"})
    EXPECT_TRUE(fs::exists(out / f)) << f;
  const nlohmann::json init = Evaluate(out / "init"), final = Evaluate(out / "sparse");
  EXPECT_EQ(final["images_registered"], 24);
  EXPECT_LT(final["rot_err_deg_median"].get<double>(), 0.05);
  EXPECT_LT(final["center_err_rel_median"].get<double>(), 0.005);
  EXPECT_LT(final["sigma_rms"].get<double>(), 0.9 * init["sigma_rms"].get<double>());

  ASSERT_EQ(Run("reconstruct" + tracks + " --out " + again.string() + " --workspace " + out.string()).code, 0);
  // Same poses up to the text round trip of the stored artefacts (17 significant digits).
  const pgba::Reconstruction a = pgba::ReadColmapText((out / "sparse").string());
  const pgba::Reconstruction b = pgba::ReadColmapText((again / "sparse").string());
  ASSERT_EQ(a.images.size(), b.images.size());
  for (const auto& [id, im] : a.images) {
    EXPECT_LT((im.pose.C() - b.images.at(id).pose.C()).norm(), 1e-6 * 1000.0) << im.name;  // 1 mm on ~1 km
    EXPECT_LT(pgba::RotationAngleDeg(im.pose.R(), b.images.at(id).pose.R()), 1e-6) << im.name;
  }
  std::ifstream in(again / "report.json");
  const nlohmann::json report = nlohmann::json::parse(in);
  EXPECT_TRUE(report["stages"]["local_hessians"].contains("read_from"));
  EXPECT_FALSE(report["stages"].contains("triplets"));  // the initialisation was not re-run
}

TEST_F(ReconstructCli, ForeignOrIncompleteWorkspaceIsAnErrorNamingTheFile) {
  const fs::path ws = dir_ / "ws_other";
  ASSERT_EQ(Run("reconstruct --tracks " + (dir_ / "other" / "input").string() + " --out " + ws.string()).code, 0);
  const std::string tracks = " --tracks " + (dir_ / "scene" / "input").string();
  pgba::test::CliResult r = Run("reconstruct" + tracks + " --out " + (dir_ / "x").string() + " --workspace " + ws.string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find((ws / "pairs.json").string()), std::string::npos) << r.output;
  fs::remove(ws / "triplets.json");
  r = Run("reconstruct" + tracks + " --out " + (dir_ / "x").string() + " --workspace " + ws.string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("triplets.json: missing"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir_ / "x" / "sparse"));
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
