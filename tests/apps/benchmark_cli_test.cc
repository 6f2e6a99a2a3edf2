// `pgba benchmark` end to end on a small synthetic orbit written by `pgba synth` (40 images,
// 0.5 px noise, 2% outliers; under 1 s): exit 0, benchmark.json with the keys benchmark.h
// documents for every method, numbers that agree with the scene's truth (every image
// registered, sigma at the level the noise and the degrees of freedom predict, rotations
// near the ground truth, unknowns counted as 6 per image + 3 per point or + 7 per motion),
// one model per method, the convergence plot and the printed table. Bad options exit 2 with
// one "error: ..." line (usage errors end in the --help hint) and leave no benchmark.json.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "pgba/io/colmap_text.h"
#include "tests/apps/cli_runner.h"

namespace pgba {
namespace {
namespace fs = std::filesystem;

constexpr int kImages = 40;  // 9 degrees apart on the orbit: enough triangles of verified pairs

class BenchmarkCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("pgba_benchmark_cli_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    const test::CliResult r = test::RunPgba("-v 0 synth --scenario orbit --images " + std::to_string(kImages) +
                                            " --points 4000 --seed 3 --noise 0.5 --outliers 0.02 --out " +
                                            (dir_ / "scene").string());
    ASSERT_EQ(r.code, 0) << r.output;
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }

  static std::vector<std::string> Lines(const std::string& text) {
    std::vector<std::string> lines;
    std::istringstream in(text);
    for (std::string l; std::getline(in, l);)
      if (!l.empty()) lines.push_back(l);
    return lines;
  }
  static void ExpectError(const test::CliResult& r, const std::string& mention, bool usage) {
    EXPECT_EQ(r.code, 2) << r.output;
    const std::vector<std::string> lines = Lines(r.output);
    ASSERT_EQ(lines.size(), 1u) << r.output;
    const std::string hint = " (usage: pgba benchmark --help)";
    if (usage) {
      ASSERT_GE(lines[0].size(), hint.size());
      EXPECT_EQ(lines[0].substr(lines[0].size() - hint.size()), hint) << lines[0];
    }
    EXPECT_EQ(lines[0].rfind("error: ", 0), 0u) << lines[0];
    EXPECT_NE(lines[0].find(mention), std::string::npos) << lines[0];
  }
  static fs::path dir_;
};
fs::path BenchmarkCli::dir_;

TEST_F(BenchmarkCli, WritesTheDocumentedReportWithNumbersMatchingTheTruth) {
  const fs::path out = dir_ / "out";
  const test::CliResult r = test::RunPgba("-v 0 benchmark --tracks " + (dir_ / "scene" / "input").string() + " --gt " +
                                          (dir_ / "scene" / "gt").string() + " --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("Table 1"), std::string::npos) << r.output;
  for (const char* f : {"benchmark.json", "convergence.svg"}) EXPECT_TRUE(fs::exists(out / f)) << f;
  std::ifstream in(out / "benchmark.json");
  const nlohmann::json j = nlohmann::json::parse(in);

  ASSERT_TRUE(j.contains("init") && j["init"].contains("stages")) << j.dump().substr(0, 400);
  EXPECT_EQ(j["init"]["images_registered"], kImages);
  EXPECT_EQ(j["tracks"], (dir_ / "scene" / "input").string());
  EXPECT_EQ(j["rotation_outliers"], 0.0);
  for (const char* stage : {"pairs", "triplets", "global_init"}) EXPECT_TRUE(j["init"]["stages"].contains(stage)) << stage;

  ASSERT_TRUE(j.contains("methods"));
  // The default motions are whole tracks, not solved locally: Aver_BA, which averages what
  // local BAs solved, would hand back the linearisation poses; it is reported as not run.
  EXPECT_FALSE(j["methods"].contains("averaging"));
  ASSERT_TRUE(j.contains("skipped") && j["skipped"].contains("averaging"));
  EXPECT_NE(j["skipped"]["averaging"].get<std::string>().find("paper_triplets.json"), std::string::npos);
  EXPECT_NE(r.output.find("averaging not run"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(out / "models" / "averaging"));
  for (const char* name : {"pointless", "pointbased"}) {
    SCOPED_TRACE(name);
    ASSERT_TRUE(j["methods"].contains(name));
    const nlohmann::json& m = j["methods"][name];
    for (const char* key : {"sigma_init", "sigma_final", "params", "iterations", "adjust_seconds", "prepare_seconds",
                            "peak_rss_mb", "rot_err_deg_median", "rel_rot_err_deg_median", "rel_dir_err_deg_median",
                            "convergence", "images_registered", "images_excluded", "details"})
      EXPECT_TRUE(m.contains(key)) << key;
    EXPECT_EQ(m["images_registered"], kImages);
    EXPECT_EQ(m["images_excluded"], 0);
    EXPECT_GT(m["adjust_seconds"].get<double>(), 0.0);
    EXPECT_GE(m["prepare_seconds"].get<double>(), 0.0);
    EXPECT_GT(m["peak_rss_mb"].get<double>(), 0.0);
    // The curve: the shared initialisation, then one sigma per iteration, ending at the final one.
    const nlohmann::json& curve = m["convergence"];
    ASSERT_EQ(curve.size(), m["iterations"].get<size_t>() + 1);
    // (The curve's sigma is triangulated on its own: equal to ~1e-9.)
    EXPECT_NEAR(curve.front().get<double>(), m["sigma_init"].get<double>(), 1e-6);
    EXPECT_NEAR(curve.back().get<double>(), m["sigma_final"].get<double>(), 1e-6);
    EXPECT_DOUBLE_EQ(m["sigma_init"].get<double>(), j["init"]["sigma_rms"].get<double>());
    // The model of the method: every image, in COLMAP text.
    EXPECT_EQ(ReadColmapText((out / "models" / name).string()).images.size(), static_cast<size_t>(kImages));
    std::cout << name << ": sigma " << m["sigma_init"] << " -> " << m["sigma_final"] << ", params " << m["params"]
              << ", iterations " << m["iterations"] << ", rot err median " << m["rot_err_deg_median"] << " deg, rel "
              << m["rel_rot_err_deg_median"] << "\n";
  }
  const nlohmann::json& pb = j["methods"]["pointbased"];
  const nlohmann::json& pl = j["methods"]["pointless"];
  // Sigma against the noise (0.5 px per coordinate): a least-squares fit of P unknowns (7 of
  // them gauge) to 2M coordinates leaves E ||r||^2 = 2 (1 - (P - 7) / 2M) 0.25 px^2 per
  // observation, the point-based BA's P and M below. The robust passes and the 4 px inlier
  // cut trim the tail a little: measured 0.974x (point-based), 0.980x (pointless).
  const long M = j["init"]["details"]["observations"].get<long>();
  const long P = pb["params"].get<long>();
  const double expected = 0.5 * std::sqrt(2.0 * (1.0 - (P - 7.0) / (2.0 * M)));
  for (const nlohmann::json* m : {&pb, &pl}) {
    EXPECT_GT((*m)["sigma_final"].get<double>(), 0.95 * expected) << expected;
    EXPECT_LT((*m)["sigma_final"].get<double>(), 1.01 * expected) << expected;
    // Against the ground truth: measured 0.039 (pointless), 0.044 deg (point-based), from an
    // initialisation at 0.24 deg; relative rotations 0.32x and 0.36x of the initial error.
    EXPECT_LT((*m)["rot_err_deg_median"].get<double>(), 0.05);
    EXPECT_LT((*m)["rel_rot_err_deg_median"].get<double>(), 0.4 * j["init"]["rel_rot_err_deg_median"].get<double>());
  }
  // Unknowns: point-based 6 per image and 3 per point it adjusts (at most every track, at
  // least the tracks it triangulated but for its 4 px filter); pointless 6 per image and 7
  // per motion (its similarity), at most a quarter of the point-based count.
  const long tracks = j["init"]["details"]["tracks"].get<long>();
  const long triangulated = j["init"]["details"]["tracks_triangulated"].get<long>();
  EXPECT_EQ((P - 6L * kImages) % 3, 0);
  EXPECT_LE((P - 6L * kImages) / 3, tracks);
  EXPECT_GE((P - 6L * kImages) / 3, triangulated * 95 / 100);
  const long motions = pl["details"]["method"]["motions"].get<long>();
  EXPECT_EQ(pl["params"].get<long>(), 6L * kImages + 7L * motions);
  EXPECT_LE(4 * pl["params"].get<long>(), P);
}

// --start replaces the initialisation by a given model's poses: from the ground truth every
// method starts at the noise level (the initial reprojection error is the truth's, below the
// averaging's start), and the result is the same minimum for both. A start without one image
// of the scene is an input error naming its file.
TEST_F(BenchmarkCli, StartsEveryMethodFromAGivenModel) {
  const std::string tracks = (dir_ / "scene" / "input").string();
  const std::string gt = (dir_ / "scene" / "gt").string();
  const auto run = [&](const std::string& name, const std::string& extra) {
    const fs::path out = dir_ / name;
    const test::CliResult r = test::RunPgba("-v 0 benchmark --tracks " + tracks + " --gt " + gt +
                                            " --no-convergence --out " + out.string() + extra);
    EXPECT_EQ(r.code, 0) << r.output;
    std::ifstream in(out / "benchmark.json");
    return std::make_pair(r.output, nlohmann::json::parse(in));
  };
  const auto [averaged_log, averaged] = run("from_averaging", "");
  const auto [truth_log, truth] = run("from_truth", " --start " + gt);
  EXPECT_NE(truth_log.find("start: " + std::to_string(kImages) + " of " + std::to_string(kImages) + " initial poses"),
            std::string::npos)
      << truth_log;
  EXPECT_EQ(truth.value("start", ""), gt);
  for (const char* method : {"pointless", "pointbased"}) {
    const nlohmann::json& a = averaged["methods"][method];
    const nlohmann::json& t = truth["methods"][method];
    EXPECT_LT(t["sigma_init"].get<double>(), 0.9 * a["sigma_init"].get<double>()) << method;
    EXPECT_LT(t["sigma_init"].get<double>(), 1.1 * t["sigma_final"].get<double>()) << method;
  }
  const double pl = truth["methods"]["pointless"]["rel_rot_err_deg_median"].get<double>();
  const double pb = truth["methods"]["pointbased"]["rel_rot_err_deg_median"].get<double>();
  EXPECT_NEAR(pl, pb, 0.02 * pb);

  // A model that names none of the scene's images.
  const fs::path other = dir_ / "other_model";
  fs::create_directories(other);
  std::ofstream(other / "cameras.txt") << "1 PINHOLE 640 480 500 500 320 240\n";
  std::ofstream(other / "images.txt") << "1 1 0 0 0 0 0 0 1 not_in_the_scene.jpg\n\n";
  std::ofstream(other / "points3D.txt") << "";
  const fs::path out = dir_ / "bad_start";
  ExpectError(test::RunPgba("-v 0 benchmark --tracks " + tracks + " --start " + other.string() + " --out " + out.string()),
              (other / "images.txt").string(), false);
  EXPECT_FALSE(fs::exists(out / "benchmark.json"));
  const std::string missing = (dir_ / "no_such_start").string();
  ExpectError(test::RunPgba("-v 0 benchmark --tracks " + tracks + " --start " + missing + " --out " + out.string()),
              missing, false);
}

TEST_F(BenchmarkCli, BadOptionsExitTwoWithAnErrorLineAndNoReport) {
  const std::string tracks = (dir_ / "scene" / "input").string();
  const fs::path out = dir_ / "bad";
  // Usage errors: one line, the error and then the hint "(usage: pgba benchmark --help)".
  ExpectError(test::RunPgba("-v 0 benchmark --tracks " + tracks + " --out " + out.string() + " --rotation-outliers 1.5"),
              "--rotation-outliers", true);
  ExpectError(test::RunPgba("-v 0 benchmark --out " + out.string()), "--tracks", true);
  ExpectError(test::RunPgba("-v 0 benchmark --tracks " + tracks + " --out " + out.string() + " --no-such-flag"),
              "--no-such-flag", true);
  // Input errors: one line naming the file.
  const std::string missing = (dir_ / "no_such_model").string();
  ExpectError(test::RunPgba("-v 0 benchmark --tracks " + missing + " --out " + out.string()), missing, false);
  const std::string missing_gt = (dir_ / "no_such_gt").string();
  ExpectError(test::RunPgba("-v 0 benchmark --tracks " + tracks + " --gt " + missing_gt + " --out " + out.string()),
              missing_gt, false);
  EXPECT_FALSE(fs::exists(out / "benchmark.json"));
}

}  // namespace
}  // namespace pgba
