// `pgba run` on a rendered ring (36 views of the textured room, 10 degrees apart) with a
// planted gap: views 9-16 and 27-35 removed, the two arcs left (0-8 and 17-26) share no
// verified pair, so the view graph splits in two: two models, sparse/0 and sparse/1, each
// within 0.05 deg of the truth after its own similarity, every image's fate "triplets" in
// one of them. With view 12 restored, the bridge joins the arcs: one model of every image.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "pgba/io/colmap_text.h"
#include "tests/apps/cli_runner.h"

namespace {
namespace fs = std::filesystem;

class ComponentsCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("pgba_components_cli_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    const pgba::test::CliResult r =
        pgba::test::RunPgba("-v 0 synth --render --images 36 --seed 2 --out " + (dir_ / "ring").string());
    ASSERT_EQ(r.code, 0) << r.output;
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }

  // `pgba run` on the views `views` of the ring (links in a folder of their own); report.json.
  static nlohmann::json RunOn(const std::string& name, const std::vector<int>& views) {
    const fs::path images = dir_ / name / "images", out = dir_ / name / "out";
    fs::create_directories(images);
    for (int v : views) {
      char file[32];
      std::snprintf(file, sizeof(file), "room_%03d.png", v);
      fs::create_symlink(dir_ / "ring" / "images" / file, images / file);
    }
    const pgba::test::CliResult r =
        pgba::test::RunPgba("-v 0 run --images " + images.string() + " --calib " + (dir_ / "ring" / "cameras.txt").string() +
                            " --gt " + (dir_ / "ring" / "gt").string() + " --out " + out.string());
    EXPECT_EQ(r.code, 0) << r.output;
    std::ifstream in(out / "report.json");
    return nlohmann::json::parse(in);
  }
  static std::vector<int> Range(int first, int last) {
    std::vector<int> v;
    for (int i = first; i <= last; ++i) v.push_back(i);
    return v;
  }
  static fs::path dir_;
};
fs::path ComponentsCli::dir_;

TEST_F(ComponentsCli, PlantedGapGivesTwoAccurateModelsAndABridgeOne) {
  std::vector<int> arcs = Range(0, 8);
  for (int v : Range(17, 26)) arcs.push_back(v);
  const nlohmann::json split = RunOn("split", arcs);
  ASSERT_EQ(split["status"], "ok");
  EXPECT_EQ(split["images_registered"], 19);
  ASSERT_EQ(split["models"].size(), 2u);
  const fs::path out = dir_ / "split" / "out";
  std::set<std::string> seen;
  for (int m = 0; m < 2; ++m) {
    const nlohmann::json& e = split["models"][m]["evaluation"];
    std::cout << "model " << m << ": " << split["models"][m]["images_registered"] << " images, rotation error median "
              << e["rot_err_deg_median"] << " max " << e["rot_err_deg_max"] << " deg\n";
    EXPECT_LT(e["rot_err_deg_max"].get<double>(), 0.05);
    const pgba::Reconstruction model = pgba::ReadColmapText((out / "sparse" / std::to_string(m)).string());
    EXPECT_EQ(model.images.size(), split["models"][m]["images_registered"].get<size_t>());
    EXPECT_GE(model.images.size(), 9u);
    // The arcs are the models: no model mixes views of both.
    int low = 0;
    for (const auto& [id, image] : model.images) {
      low += image.name < "room_009.png";
      EXPECT_TRUE(seen.insert(image.name).second) << image.name << " in two models";
    }
    EXPECT_TRUE(low == 0 || low == static_cast<int>(model.images.size())) << "model " << m;
    EXPECT_TRUE(fs::is_regular_file(out / "sparse" / std::to_string(m) / "points.ply"));
  }
  // sparse/ is the largest model; every image's fate: in a model by its triplets.
  EXPECT_EQ(pgba::ReadColmapText((out / "sparse").string()).images.size(),
            split["models"][0]["images_registered"].get<size_t>());
  ASSERT_EQ(split["image_fates"].size(), 19u);
  for (const nlohmann::json& fate : split["image_fates"]) EXPECT_EQ(fate["registered_by"], "triplets") << fate.dump();
  EXPECT_LT(split["evaluation_models"]["rot_err_deg_max"].get<double>(), 0.05);

  arcs.push_back(12);
  const nlohmann::json bridged = RunOn("bridged", arcs);
  ASSERT_EQ(bridged["status"], "ok");
  EXPECT_EQ(bridged["images_registered"], 20);
  ASSERT_EQ(bridged["models"].size(), 1u);
  const nlohmann::json& e = bridged["models"][0]["evaluation"];
  std::cout << "bridged: rotation error median " << e["rot_err_deg_median"] << " max " << e["rot_err_deg_max"]
            << " deg\n";
  EXPECT_LT(e["rot_err_deg_max"].get<double>(), 0.05);
  EXPECT_FALSE(fs::exists(dir_ / "bridged" / "out" / "sparse" / "1"));
}

}  // namespace
