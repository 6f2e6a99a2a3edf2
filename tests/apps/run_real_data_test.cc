// `pgba run` end to end on real photographs with ground truth (shared/datasets), on the
// dataset where the view graph is weakest: temple_sparse_ring,
// a 360 degree Middlebury ring whose 43 degree gap (templeSR0014 - templeSR0002) leaves no
// match, so the ring is an open chain, and two of whose hinges (templeSR0005, templeSR0009)
// are shared by no verified triangle: only open triplets hold it together. Every image must
// be registered with a median rotation error below 0.5 deg against the ground truth.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <nlohmann/json.hpp>

#include "tests/apps/cli_runner.h"
#include "tests/support/shared_data.h"

namespace {
namespace fs = std::filesystem;

// `pgba run --config configs/object_ring.json --gt` on a shared dataset into a fresh OUT;
// its report.json (null when the dataset is missing).
nlohmann::json RunObjectRing(const std::string& dataset, const fs::path& out) {
  const fs::path data = fs::path(PGBA_SHARED_DIR) / "datasets" / dataset;
  if (!fs::exists(data / "images")) return nullptr;
  fs::remove_all(out);
  const pgba::test::CliResult r = pgba::test::RunPgba(
      "-v 0 run --images " + (data / "images").string() + " --calib " + (data / "cameras.txt").string() + " --gt " +
      (data / "gt").string() + " --config " + PGBA_SOURCE_DIR "/configs/object_ring.json --out " + out.string());
  EXPECT_EQ(r.code, 0) << r.output;
  std::ifstream in(out / "report.json");
  return nlohmann::json::parse(in);
}

TEST(RunRealData, TempleSparseRingEveryImageRegistered) {
  const fs::path out = fs::temp_directory_path() / ("pgba_run_temple_" + std::to_string(::getpid()));
  const nlohmann::json report = RunObjectRing("temple_sparse_ring", out);
  PGBA_NEED_SHARED_DATA(!report.is_null(), "temple_sparse_ring");
  ASSERT_EQ(report.value("status", ""), "ok");
  const nlohmann::json& e = report["evaluation"];
  std::cout << "temple_sparse_ring: " << e["images_registered"] << "/16 registered, rotation error median "
            << e["rot_err_deg_median"] << " max " << e["rot_err_deg_max"] << " deg, centre error median "
            << e["center_err_rel_median"] << " of the extent\n";
  EXPECT_EQ(e["images_registered"], 16);
  EXPECT_LT(e["rot_err_deg_median"].get<double>(), 0.5);
  EXPECT_LT(e["center_err_rel_median"].get<double>(), 0.01);
  EXPECT_GE(report["stages"]["triplets"]["open_selected"].get<int>(), 1);
  fs::remove_all(out);
}

// dino_sparse_ring (weakly textured plaster, ~230 SIFT features per image at the fixed
// threshold, where COLMAP registers nothing): the object_ring preset's adaptive contrast
// threshold lowers the threshold of every image, weak pairs confirmed by a third view (and
// kept as a chain end's only link) connect more images, the registered images (6 measured,
// 4 without the weak pairs; docs/benchmarks.md "Weakly textured objects" says why not all 16) are
// within 0.33 deg of the ground truth (the point-based BA's optimum on these tracks, where the
// converged pointless BA ends: max 0.326 deg), and report.html shows the adapted images and the view
// graph, drawn and in words.
TEST(RunRealData, DinoSparseRingAdaptiveContrastRegistersAccurately) {
  const fs::path out = fs::temp_directory_path() / ("pgba_run_dino_" + std::to_string(::getpid()));
  const nlohmann::json report = RunObjectRing("dino_sparse_ring", out);
  PGBA_NEED_SHARED_DATA(!report.is_null(), "dino_sparse_ring");
  ASSERT_EQ(report.value("status", ""), "ok");
  const nlohmann::json& e = report["evaluation"];
  const nlohmann::json& f = report["stages"]["features"];
  std::cout << "dino_sparse_ring: " << f["features_mean"] << " features per image, " << e["images_registered"]
            << "/16 registered, rotation error median " << e["rot_err_deg_median"] << " max " << e["rot_err_deg_max"]
            << " deg; pair verdicts " << report["stages"]["match"]["pair_verdicts"] << "\n";
  EXPECT_EQ(f["adapted_contrast_threshold"].size(), 16u);
  EXPECT_GT(f["features_mean"].get<double>(), 1000.0);
  EXPECT_GE(e["images_registered"].get<int>(), 6);
  EXPECT_LT(e["rot_err_deg_median"].get<double>(), 0.25);
  EXPECT_LT(e["rot_err_deg_max"].get<double>(), 0.33);
  const nlohmann::json& verdicts = report["stages"]["match"]["pair_verdicts"];
  EXPECT_GE(verdicts.value("verified", 0), 5);
  EXPECT_GE(verdicts.value("confirmed", 0), 6);
  EXPECT_GE(verdicts.value("leaf", 0), 2);
  std::ifstream page(out / "report.html");
  const std::string html((std::istreambuf_iterator<char>(page)), std::istreambuf_iterator<char>());
  EXPECT_NE(html.find("<h2>View graph</h2>"), std::string::npos);
  EXPECT_NE(html.find("connected to (inliers)"), std::string::npos);
  EXPECT_NE(html.find("lowered SIFT contrast threshold"), std::string::npos);
  EXPECT_TRUE(fs::is_regular_file(out / "matching" / "pairs.txt"));
  fs::remove_all(out);
}

// Every part of dino_sparse_ring that the matches connect, each a model of its own: the
// ring's two arcs (6 images each, measured) are models 0 and 1 in sparse/0 and sparse/1,
// every image with a verified pair of the front end is in a model, every other image is named
// in report.json with the reason; each model is evaluated with its own similarity.
// Measured: model 0 rotation error median 0.23 max 0.33 deg, model 1 median 0.74 max 1.17
// deg (the point-based BA on the same tracks: 1.19 deg max). Model 1's rotations are within
// 0.48 deg of the truth up to one common rotation; its centre similarity is tilted 0.7 deg by
// dinoSR0015, which hangs on its one pair (15-16) with its centre 0.46% of the ring's extent
// off, and aligned without it every rotation is within 0.43 deg (bench/alignment_tilt.py).
// No verified pair joins the two models, and the four images in neither have no match.
// dino_sparse_ring with the default configuration: 233 SIFT features per image leave one image
// triplet (3 images). The averaging puts them 0.37 deg off the triplet's own rotations (21 px at
// this focal), where the whole-track motion's quadratic model misleads: the pointless BA's
// first step raises the reprojection cost. The motions are then taken again where the
// triplets' pointless BA puts the poses, and the images are placed as their triplet's own
// bundle adjustment does; relative errors, as three centres leave a similarity ill-posed.
TEST(RunRealData, DinoSparseRingDefaultConfigStartsAgainFromTheTripletsWhenStuck) {
  const fs::path data = fs::path(PGBA_SHARED_DIR) / "datasets" / "dino_sparse_ring";
  PGBA_NEED_SHARED_DATA(fs::exists(data / "images"), data.string());
  const fs::path out = fs::temp_directory_path() / ("pgba_run_dino_default_" + std::to_string(::getpid()));
  fs::remove_all(out);
  const pgba::test::CliResult r = pgba::test::RunPgba(
      "-v 0 run --images " + (data / "images").string() + " --calib " + (data / "cameras.txt").string() + " --gt " +
      (data / "gt").string() + " --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.output;
  std::ifstream in(out / "report.json");
  const nlohmann::json report = nlohmann::json::parse(in);
  EXPECT_TRUE(report["stages"].contains("global_ba_before_triplet_start"));
  EXPECT_EQ(report["stages"]["global_ba"].value("converged", false), true);
  const nlohmann::json& e = report["evaluation"];
  ASSERT_EQ(e["images_registered"], 3);
  std::cout << "dino_sparse_ring, default configuration: relative rotation error median "
            << e["rel_rot_err_deg_median"] << " max " << e["rel_rot_err_deg_max"] << " deg\n";
  EXPECT_LT(e["rel_rot_err_deg_max"].get<double>(), 0.75);
  fs::remove_all(out);
}

TEST(RunRealData, DinoSparseRingEveryConnectedPartIsAModel) {
  const fs::path out = fs::temp_directory_path() / ("pgba_run_dino_models_" + std::to_string(::getpid()));
  const nlohmann::json report = RunObjectRing("dino_sparse_ring", out);
  PGBA_NEED_SHARED_DATA(!report.is_null(), "dino_sparse_ring");
  ASSERT_EQ(report.value("status", ""), "ok");
  // The images of the front end's verified pairs.
  std::set<std::string> paired;
  {
    std::map<int, std::string> names;
    std::ifstream images(out / "tracks" / "images.txt");
    for (std::string line; std::getline(images, line);) {
      std::istringstream in(line);
      int id;
      double q[7];
      int camera;
      std::string name;
      if (line.empty() || line[0] == '#' || !(in >> id >> q[0] >> q[1] >> q[2] >> q[3] >> q[4] >> q[5] >> q[6] >> camera >> name))
        continue;
      names[id] = name;
      std::getline(images, line);  // its observations
    }
    std::ifstream geometries(out / "matching" / "two_view_geometries.txt");
    for (std::string line; std::getline(geometries, line);) {
      std::istringstream in(line);
      int a, b;
      if (line.empty() || line[0] == '#' || !(in >> a >> b)) continue;
      paired.insert(names[a]);
      paired.insert(names[b]);
    }
  }
  ASSERT_GE(paired.size(), 12u);
  ASSERT_EQ(report["image_fates"].size(), 16u);
  for (const nlohmann::json& fate : report["image_fates"]) {
    const std::string name = fate["image"];
    if (paired.count(name)) {
      EXPECT_FALSE(fate["model"].is_null()) << fate.dump();
    } else {
      EXPECT_TRUE(fate["model"].is_null()) << fate.dump();
      // No verified pair: its matches were all refused (no track) or its tracks verify no pair.
      const std::string reason = fate.value("reason", "");
      EXPECT_TRUE(reason == "no feature matched to another image" ||
                  reason == "no image pair verified (too few matches agreeing on one relative pose)")
          << fate.dump();
    }
  }
  EXPECT_EQ(report["images_registered"].get<size_t>(), paired.size());
  const nlohmann::json& models = report["models"];
  ASSERT_GE(models.size(), 2u);
  size_t images = 0;
  for (size_t m = 0; m < models.size(); ++m) {
    const nlohmann::json& e = models[m]["evaluation"];
    std::cout << "dino_sparse_ring model " << m << ": " << models[m]["images_registered"]
              << " images, rotation error median " << e["rot_err_deg_median"] << " max " << e["rot_err_deg_max"]
              << " deg\n";
    EXPECT_GE(models[m]["images_registered"].get<int>(), 3);
    EXPECT_LT(e["rot_err_deg_median"].get<double>(), 1.0);
    EXPECT_LT(e["rot_err_deg_max"].get<double>(), 1.5);
    images += models[m]["images_registered"].get<size_t>();
    EXPECT_TRUE(fs::is_regular_file(out / "sparse" / std::to_string(m) / "images.txt")) << m;
    EXPECT_TRUE(fs::is_regular_file(out / "sparse" / std::to_string(m) / "points.ply")) << m;
  }
  EXPECT_EQ(images, paired.size());
  EXPECT_EQ(report["evaluation_models"]["images_registered"].get<size_t>(), paired.size());
  EXPECT_FALSE(fs::exists(out / "sparse" / std::to_string(models.size())));
  fs::remove_all(out);
}

}  // namespace
