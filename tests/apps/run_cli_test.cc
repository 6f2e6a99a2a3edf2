// `pgba run` end to end on a rendered synthetic scene (photographs of a textured room from a
// ring of known poses): every image registered, rotations within 0.1 deg of the truth,
// every output written; a re-run reuses the features and tracks; an empty folder or a
// folder of non-images fails with exit code 2, a failed report.json and no report.html.
// report.html says what report.json and the written model say: images registered, points and
// observations of sparse/, every stage with its seconds in the stages' order and their
// total, the ground-truth rotation errors, one camera per registered image in the top view and
// in the 3D view (with every point of the model), the pairs the view graph verified;
// self-contained (scripts inline, nothing fetched).
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "pgba/io/colmap_text.h"
#include "tests/apps/cli_runner.h"

namespace {
namespace fs = std::filesystem;

std::string Slurp(const fs::path& p) {
  std::ifstream in(p);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

std::string Fixed(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), format, v);
  return buf;
}

size_t Count(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + what.size())) ++n;
  return n;
}

// report.html against report.json and the model written beside it (`images`: the scene's).
void ExpectHtmlMatchesReport(const fs::path& out, const nlohmann::json& r, int images) {
  const std::string html = Slurp(out / "report.html");
  ASSERT_FALSE(html.empty());
  auto row = [&](const std::string& key, const std::string& value) {
    EXPECT_NE(html.find("<th>" + key + "</th><td>" + value + "</td>"), std::string::npos) << key << " = " << value;
  };
  ASSERT_EQ(r["images_registered"], images);
  row("images registered", std::to_string(images) + " / " + std::to_string(r["images_input"].get<int>()));
  const pgba::Reconstruction model = pgba::ReadColmapText((out / "sparse").string());
  EXPECT_EQ(model.images.size(), static_cast<size_t>(images));
  row("points", std::to_string(model.points3D.size()));
  row("observations", std::to_string(model.NumObservations()));
  row("unknowns of the pointless global BA", std::to_string(r["params"].get<long>()));
  const nlohmann::json& e = r["evaluation"];
  row("rotation error vs ground truth, median / max (deg)",
      Fixed("%.4f", e["rot_err_deg_median"].get<double>()) + " / " + Fixed("%.4f", e["rot_err_deg_max"].get<double>()));
  row("sigma median (px)", Fixed("%.4f", e["sigma_median"].get<double>()));
  // Every stage, in the order report.json gives, with its seconds; the total their sum.
  std::vector<std::pair<int, std::string>> order;
  for (const auto& [name, st] : r["stages"].items()) order.push_back({st.value("order", 0), name});
  std::sort(order.begin(), order.end());
  ASSERT_GE(order.size(), 7u);
  size_t last = 0;
  double total = 0.0;
  for (const auto& [o, name] : order) {
    const double seconds = r["stages"][name].value("seconds", 0.0);
    total += seconds;
    const size_t at = html.find("<tr><td>" + name + "</td><td class=\"n\">" + Fixed("%.2f", seconds) + "</td>");
    ASSERT_NE(at, std::string::npos) << name;
    EXPECT_GT(at, last) << name << " out of order";
    last = at;
  }
  EXPECT_NE(html.find("<tr><th>total</th><th class=\"n\">" + Fixed("%.2f", total) + "</th>"), std::string::npos);
  // Top view: one camera marker (named) per registered image.
  const size_t top = html.find("<h2>Top view</h2>"), graph = html.find("<h2>View graph</h2>");
  ASSERT_NE(top, std::string::npos);
  ASSERT_NE(graph, std::string::npos);
  ASSERT_LT(top, graph);
  const std::string top_view = html.substr(top, graph - top);
  EXPECT_EQ(Count(top_view, "</title></circle>"), static_cast<size_t>(images));
  for (const auto& [id, im] : model.images) EXPECT_NE(top_view.find("<title>" + im.name + "</title>"), std::string::npos);
  // View graph: the pairs the view graph stage verified.
  const int pairs = r["stages"]["pairs"]["pairs_kept"].get<int>();
  EXPECT_GT(pairs, images);
  EXPECT_NE(html.find("<h2>View graph</h2><p>" + std::to_string(pairs) + " verified pairs"), std::string::npos);
  // 3D view: one camera per registered image, by name, and every point of the model.
  const std::string data_start = "<script type=\"application/json\" id=\"pgba-view3d-data\">";
  const size_t data = html.find(data_start);
  ASSERT_NE(data, std::string::npos);
  const size_t data_end = html.find("</script>", data);
  ASSERT_NE(data_end, std::string::npos);
  const nlohmann::json view = nlohmann::json::parse(html.substr(data + data_start.size(), data_end - data - data_start.size()));
  std::vector<std::string> view_names, model_names;
  for (const auto& c : view["cameras"]) view_names.push_back(c["name"]);
  for (const auto& [id, im] : model.images) model_names.push_back(im.name);
  std::sort(view_names.begin(), view_names.end());
  std::sort(model_names.begin(), model_names.end());
  EXPECT_EQ(view_names, model_names);
  EXPECT_EQ(view["points"].size(), 3 * model.points3D.size());
  // Self-contained: scripts inline, nothing fetched.
  EXPECT_EQ(html.find("<script src"), std::string::npos);
  EXPECT_EQ(html.find("src=\"http"), std::string::npos);
  EXPECT_EQ(html.find("href=\"http"), std::string::npos);
}

class RunCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("pgba_run_cli_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    ASSERT_EQ(Run("synth --render --images 14 --width 480 --height 360 --seed 2 --out " + (dir_ / "scene").string()),
              0);
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }

  static int Run(const std::string& args) {
    last_ = pgba::test::RunPgba("-v 0 " + args);
    return last_.code;
  }
  static nlohmann::json Json(const fs::path& p) {
    std::ifstream in(p);
    return nlohmann::json::parse(in);
  }
  static std::string Stderr() { return last_.output; }
  static fs::path dir_;
  static pgba::test::CliResult last_;
};
fs::path RunCli::dir_;
pgba::test::CliResult RunCli::last_;

TEST_F(RunCli, RenderedSceneEveryImageRegisteredAndAccurate) {
  const fs::path out = dir_ / "out";
  const std::string args = "run --images " + (dir_ / "scene" / "images").string() + " --calib " +
                           (dir_ / "scene" / "cameras.txt").string() + " --gt " + (dir_ / "scene" / "gt").string() +
                           " --out " + out.string();
  ASSERT_EQ(Run(args), 0) << Stderr();
  for (const char* f : {"sparse/images.txt", "points.ply", "report.json", "report.html", "log.txt", "tracks/key.json"})
    EXPECT_TRUE(fs::exists(out / f)) << f;
  const nlohmann::json r = Json(out / "report.json");
  EXPECT_EQ(r["status"], "ok");
  const nlohmann::json& e = r["evaluation"];
  EXPECT_EQ(e["images_registered"], 14);
  EXPECT_LT(e["rot_err_deg_median"].get<double>(), 0.1);
  EXPECT_LT(e["rot_err_deg_max"].get<double>(), 0.3);
  EXPECT_LT(e["center_err_rel_median"].get<double>(), 0.005);
  for (const char* stage : {"features", "match", "pairs", "triplets", "global_init", "local_hessians", "global_ba"})
    EXPECT_TRUE(r["stages"].contains(stage)) << stage;
  ExpectHtmlMatchesReport(out, r, 14);

  // The re-run continues from the workspace: cached features, reused tracks.
  ASSERT_EQ(Run(args), 0) << Stderr();
  const nlohmann::json again = Json(out / "report.json");
  EXPECT_EQ(again["stages"]["features"]["images_cached"], 14);
  EXPECT_EQ(again["stages"]["match"]["cached"], true);
  EXPECT_EQ(again["evaluation"]["images_registered"], 14);
  // Both runs' view graphs start from the front end's verified geometries (read back from
  // matching/two_view_geometries.txt by the re-run): no pair it verified is estimated again.
  for (const nlohmann::json* report : {&r, &again}) {
    const nlohmann::json& pairs = (*report)["stages"]["pairs"];
    EXPECT_GT(pairs["pairs_front_end"].get<int>(), 0) << pairs.dump();
    EXPECT_EQ(pairs["pairs_refine_fallback"], 0) << pairs.dump();
    EXPECT_EQ(pairs["pairs_ransac"].get<int>(), pairs["pairs_estimated"].get<int>() - pairs["pairs_front_end"].get<int>());
    // The convergence curve's sample covers every track of this small scene.
    EXPECT_EQ((*report)["stages"]["convergence"]["sampled"], false);
  }
  EXPECT_EQ(again["stages"]["pairs"]["pairs_front_end"], r["stages"]["pairs"]["pairs_front_end"]);
  EXPECT_EQ(again["evaluation"]["rot_err_deg_max"], r["evaluation"]["rot_err_deg_max"]);

  // A geometries file that does not fit the cached tracks: exit 2 and the file named.
  const fs::path geometries = out / "matching" / "two_view_geometries.txt";
  const fs::path saved = dir_ / "two_view_geometries.saved";
  fs::copy_file(geometries, saved);
  std::ofstream(geometries, std::ios::app) << "1 99 1 0 0 0 1 0 0 50 40 3.0\n";
  EXPECT_EQ(Run(args), 2);
  EXPECT_NE(Stderr().find(geometries.string() + ": pair (1, 99): image 99 is not in the tracks"), std::string::npos)
      << Stderr();
  std::ofstream(geometries) << "1 2 1 0 0\n";
  EXPECT_EQ(Run(args), 2);
  EXPECT_NE(Stderr().find(geometries.string() + ":1:"), std::string::npos) << Stderr();
  fs::copy_file(saved, geometries, fs::copy_options::overwrite_existing);
}

// `pgba features` on its own records which calibration it used, as `pgba run` does.
TEST_F(RunCli, FeaturesCommandRecordsTheCalibrationSource) {
  const fs::path ws = dir_ / "features_only";
  const fs::path calib = dir_ / "scene" / "cameras.txt";
  ASSERT_EQ(Run("features --images " + (dir_ / "scene" / "images").string() + " --calib " + calib.string() +
                " --out " + ws.string()),
            0)
      << Stderr();
  const nlohmann::json r = Json(ws / "report.json");
  ASSERT_TRUE(r["stages"].contains("features")) << r.dump();
  const std::string source = r["stages"]["features"]["calibration_source"].get<std::string>();
  EXPECT_EQ(source.rfind("file: ", 0), 0u) << source;
  EXPECT_NE(source.find("cameras.txt"), std::string::npos) << source;
}

TEST_F(RunCli, NoUsableImagesFailsCleanly) {
  const fs::path empty = dir_ / "empty", junk = dir_ / "junk";
  fs::create_directories(empty);
  fs::create_directories(junk);
  std::ofstream(junk / "a.jpg") << "not an image";
  std::ofstream(junk / "b.png") << "not an image either";
  const std::string calib = " --calib " + (dir_ / "scene" / "cameras.txt").string();
  for (const fs::path& images : {empty, junk}) {
    const fs::path out = dir_ / ("out_" + images.filename().string());
    EXPECT_EQ(Run("run --images " + images.string() + calib + " --out " + out.string()), 2) << images;
    EXPECT_NE(Stderr().find("error: "), std::string::npos);
    EXPECT_FALSE(fs::exists(out / "report.html")) << images;
    EXPECT_FALSE(fs::exists(out / "sparse")) << images;
    if (fs::exists(out / "report.json")) {
      EXPECT_EQ(Json(out / "report.json")["status"], "failed");
    }
  }
}

// Too few images to reconstruct (one, two, or the same photo four times), and calibration
// files that cannot be used: exit code 2, one "error:" line naming the problem, no model.
TEST_F(RunCli, TooFewOrDuplicateImagesAndBadCalibrationFailCleanly) {
  std::vector<fs::path> photos;
  for (const auto& e : fs::directory_iterator(dir_ / "scene" / "images")) photos.push_back(e.path());
  std::sort(photos.begin(), photos.end());
  ASSERT_GE(photos.size(), 2u);
  const fs::path one = dir_ / "one", two = dir_ / "two", dup = dir_ / "dup";
  for (const fs::path& d : {one, two, dup}) fs::create_directories(d);
  fs::copy_file(photos[0], one / photos[0].filename());
  fs::copy_file(photos[0], two / photos[0].filename());
  fs::copy_file(photos[1], two / photos[1].filename());
  for (int k = 0; k < 4; ++k) fs::copy_file(photos[0], dup / ("copy" + std::to_string(k) + ".png"));
  const std::string calib = " --calib " + (dir_ / "scene" / "cameras.txt").string();
  auto expect_clean_failure = [&](const std::string& args, const fs::path& out, const std::string& message) {
    EXPECT_EQ(Run(args + " --out " + out.string()), 2) << args;
    EXPECT_NE(Stderr().find("error: "), std::string::npos) << Stderr();
    EXPECT_NE(Stderr().find(message), std::string::npos) << Stderr();
    EXPECT_FALSE(fs::exists(out / "report.html")) << args;
    EXPECT_FALSE(fs::exists(out / "sparse")) << args;
  };
  expect_clean_failure("run --images " + one.string() + calib, dir_ / "out_one", "at least 3");
  expect_clean_failure("run --images " + two.string() + calib, dir_ / "out_two", "at least 3");
  expect_clean_failure("run --images " + dup.string() + calib, dir_ / "out_dup", "no verified matches");

  const fs::path bad_json = dir_ / "bad.json", bad_txt = dir_ / "bad_cameras.txt";
  std::ofstream(bad_json) << R"({"cameras": [{"camera_id": 1, "model": "PINHOLE", "width": 480, "height": 360,
                                 "params": [400, 400, 240]}]})";
  std::ofstream(bad_txt) << "1 PINHOLE 480 360 nan 400 240 180\n";
  const std::string images = "run --images " + (dir_ / "scene" / "images").string();
  expect_clean_failure(images + " --calib " + bad_json.string(), dir_ / "out_badjson", bad_json.string());
  expect_clean_failure(images + " --calib " + bad_txt.string(), dir_ / "out_badtxt", bad_txt.string());
  expect_clean_failure(images + " --calib " + (dir_ / "missing.txt").string(), dir_ / "out_missing",
                       "missing.txt");
}

}  // namespace
