// Self-calibration end to end on real photographs (bench/real_self_calibration.sh reduced to
// run in about a minute): herzjesu_p8 (Strecha et al. 2008, 8 DSLR photos without EXIF, ground
// truth poses and a lab calibration), SIFT on a faster setting (config below), three `pgba
// run`s sharing one feature cache:
//   calibrated  --calib D/cameras.txt (held): the reference;
//   prior       --calib a copy with fx, fy 10% long, --calib-prior (every BA refines them);
//   uncalibrated  no calibration file at all (SIMPLE_RADIAL prior at 1.2 max(w, h) = 33% long,
//                 focal from the view graph, focal, principal point and k refined).
// The truth is the dataset's calibration and ground truth. Rotation errors: the Sim(3)-aligned
// median (rot_err_deg_median) and the gauge-free median over all pairs (rel_rot_err_deg_median).
// Measured with this config (one run, 58 s on 2 loaded cores): calibrated rot err 0.1108 deg,
// rel 0.0227; prior +10% focal -0.10%, rot err 0.1388 (1.25x), rel 0.0414 (1.82x);
// uncalibrated focal -0.14%, rot err 0.0585 (0.53x), rel 0.0446 (1.96x) with the principal
// point estimated (0.497 and 0.106 with it held at the image centre, below). The
// relative ratio of the prior is that of the dataset's calibration freed from its own values
// (the data's self-calibration floor), so the tolerances sit just above the measure.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>

#include "pgba/io/colmap_text.h"
#include "tests/apps/cli_runner.h"
#include "tests/support/shared_data.h"

namespace {
namespace fs = std::filesystem;

nlohmann::json ReadJson(const fs::path& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

// The first camera of a COLMAP cameras.txt (the library's reader): model name and parameters.
std::pair<std::string, std::vector<double>> FirstCamera(const fs::path& path) {
  const auto cameras = pgba::ReadColmapCameras(path.string());
  if (cameras.empty()) return {};
  const pgba::Camera& c = cameras.begin()->second;
  return {pgba::CameraModelName(c.model), c.params};
}

constexpr double kPriorRelRatio = 2.0;  // measured 1.82

class RealDataSelfCalibration : public ::testing::Test {
 protected:
  // The dataset NAME of the shared folder; false when it is missing.
  bool Use(const std::string& name) {
    data_ = fs::path(PGBA_SHARED_DIR) / "datasets" / name;
    if (!fs::exists(data_ / "images") || !fs::exists(data_ / "gt")) return false;
    dir_ = fs::temp_directory_path() / ("pgba_real_selfcal_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    // The photos without their calibration beside them (`pgba run` looks for cameras.txt in
    // the image folder and its parent): links in a folder of our own. They carry no EXIF.
    fs::create_directories(dir_ / "photos" / "images");
    for (const auto& entry : fs::directory_iterator(data_ / "images"))
      fs::create_symlink(entry.path(), dir_ / "photos" / "images" / entry.path().filename());
    std::ofstream(dir_ / "fast.json") << R"({"features": {"sift": {"max_features": 4096, "max_image_size": 1600}}})";
    return true;
  }
  // A PINHOLE copy of the dataset's calibration with fx, fy 10% long, as dir_/cameras_long.txt.
  void WriteLongFocalCalibration() {
    const auto cameras = pgba::ReadColmapCameras((data_ / "cameras.txt").string());
    const pgba::Camera& c = cameras.begin()->second;
    ASSERT_EQ(c.model, pgba::CameraModel::kPinhole);
    std::ofstream(dir_ / "cameras_long.txt") << "1 PINHOLE " << c.width << " " << c.height << " " << 1.1 * c.params[0]
                                              << " " << 1.1 * c.params[1] << " " << c.params[2] << " "
                                              << c.params[3] << "\n";
  }
  void TearDown() override {
    if (!dir_.empty()) fs::remove_all(dir_);
  }

  // `pgba run` into dir_/NAME (features copied from the calibrated run when there is one).
  nlohmann::json Run(const std::string& name, const std::string& calib_args) {
    const fs::path out = dir_ / name;
    if (fs::exists(dir_ / "calibrated" / "features")) {
      fs::create_directories(out);
      fs::copy(dir_ / "calibrated" / "features", out / "features", fs::copy_options::recursive);
    }
    const pgba::test::CliResult r =
        pgba::test::RunPgba("-v 0 run --images " + (dir_ / "photos" / "images").string() + " " + calib_args +
                            (config_.empty() ? "" : " --config " + (dir_ / config_).string()) + " --gt " + (data_ / "gt").string() +
                            " --out " + out.string());
    EXPECT_EQ(r.code, 0) << r.output;
    return ReadJson(out / "report.json");
  }

  // Relative error of the refined focal(s) of dir_/NAME/sparse against the dataset's (fx, fy).
  double FocalError(const std::string& name) {
    const auto [model, est] = FirstCamera(dir_ / name / "sparse" / "cameras.txt");
    const auto [gt_model, gt] = FirstCamera(data_ / "cameras.txt");  // PINHOLE fx fy cx cy
    const double truth = 0.5 * (gt[0] + gt[1]);
    const double focal = (model == "PINHOLE" || model == "OPENCV") ? 0.5 * (est[0] + est[1]) : est[0];
    return focal / truth - 1.0;
  }

  fs::path data_, dir_;
  std::string config_ = "fast.json";  // in dir_; empty: the default config
};

TEST_F(RealDataSelfCalibration, HerzJesuWithoutCalibrationAndWithAWrongFocalPrior) {
  PGBA_NEED_SHARED_DATA(Use("herzjesu_p8"), data_.string());
  const nlohmann::json cal = Run("calibrated", "--calib " + (data_ / "cameras.txt").string());
  WriteLongFocalCalibration();
  const nlohmann::json prior = Run("prior", "--calib " + (dir_ / "cameras_long.txt").string() + " --calib-prior");
  const nlohmann::json uncal = Run("uncalibrated", "");
  const nlohmann::json &ec = cal["evaluation"], &ep = prior["evaluation"], &eu = uncal["evaluation"];
  auto line = [](const char* what, const nlohmann::json& e, double focal_error) {
    std::cout << what << ": " << e["images_registered"] << "/8, focal " << 100 * focal_error << "%, rot err "
              << e["rot_err_deg_median"] << " deg, rel rot err " << e["rel_rot_err_deg_median"] << " deg\n";
  };
  line("calibrated", ec, 0.0);
  line("prior +10%", ep, FocalError("prior"));
  line("uncalibrated", eu, FocalError("uncalibrated"));

  EXPECT_FALSE(cal["calibration_is_prior"].get<bool>());
  EXPECT_TRUE(prior["calibration_is_prior"].get<bool>());
  EXPECT_TRUE(uncal["calibration_is_prior"].get<bool>());
  EXPECT_EQ(uncal["stages"]["features"]["calibration_source"], "default-prior");  // no EXIF, no file
  for (const nlohmann::json* e : {&ec, &ep, &eu}) EXPECT_EQ((*e)["images_registered"], 8);

  // The focal within 1% of the dataset's calibration.
  EXPECT_LT(std::abs(FocalError("prior")), 0.01);
  EXPECT_LT(std::abs(FocalError("uncalibrated")), 0.01);

  const double cal_rot = ec["rot_err_deg_median"], cal_rel = ec["rel_rot_err_deg_median"];
  // The 10% prior refined: within 1.3x of the calibrated Sim(3)-aligned rotations; the gauge-free
  // relative rotations within kPriorRelRatio (measured below).
  EXPECT_LT(ep["rot_err_deg_median"].get<double>(), 1.3 * cal_rot);
  EXPECT_LT(ep["rel_rot_err_deg_median"].get<double>(), kPriorRelRatio * cal_rel);
  // Uncalibrated, the principal point is estimated too (intrinsics.
  // refine_principal_point_without_calibration): the dataset's is 23 px from the image centre
  // (0.48 deg at f 2760), which held at the centre puts every rotation off by that angle (rot
  // err 0.497 deg, rel 0.106). Measured with it estimated: rot err 0.0585 deg (0.53x), rel
  // 0.0446 (1.96x, the floor of the data's self-calibration, as with the prior above).
  EXPECT_LT(eu["rot_err_deg_median"].get<double>(), 1.3 * cal_rot);
  EXPECT_LT(eu["rel_rot_err_deg_median"].get<double>(), 2.2 * cal_rel);
  const auto [gt_model, gt] = FirstCamera(data_ / "cameras.txt");
  const auto [model, est] = FirstCamera(dir_ / "uncalibrated" / "sparse" / "cameras.txt");
  ASSERT_EQ(model, "SIMPLE_RADIAL");  // f cx cy k
  const double centre_gap = std::hypot(1536.0 - gt[2], 1024.0 - gt[3]);
  EXPECT_LT(std::hypot(est[1] - gt[2], est[2] - gt[3]), 0.5 * centre_gap);
}

// temple_sparse_ring (Middlebury, 16 views on a ring, 640 x 480, field of view 24 deg) with the
// calibration's fx, fy 10% long as a PINHOLE prior, default config. With fx and fy apart, fx
// is not observable on this ring (the global BA's standard deviation 60-240 px, 4-16%, for fx
// against ~20 px for fy; the mean focal within 1% in 0 of 6 priors 8-12% long). With one
// focal unknown and the prior's fy / fx held (intrinsics.refine_aspect_ratio false, the
// default), measured over priors 8, 10, 12% long and 8% short (bench/temple_prior_survey.sh):
// both focals within 0.08-0.36% of the dataset's, sd ~19 px.
TEST_F(RealDataSelfCalibration, TempleRingWithAWrongFocalPrior) {
  PGBA_NEED_SHARED_DATA(Use("temple_sparse_ring"), data_.string());
  config_.clear();
  const nlohmann::json cal = Run("calibrated", "--calib " + (data_ / "cameras.txt").string());
  WriteLongFocalCalibration();
  const nlohmann::json prior = Run("prior", "--calib " + (dir_ / "cameras_long.txt").string() + " --calib-prior");
  const nlohmann::json &ec = cal["evaluation"], &ep = prior["evaluation"];
  std::cout << "calibrated: " << ec["images_registered"] << "/16, rot err " << ec["rot_err_deg_median"]
            << ", rel " << ec["rel_rot_err_deg_median"] << "; prior +10%: " << ep["images_registered"]
            << "/16, focal " << 100 * FocalError("prior") << "%, rot err " << ep["rot_err_deg_median"] << ", rel "
            << ep["rel_rot_err_deg_median"] << "\n";
  EXPECT_EQ(ec["images_registered"], 16);
  EXPECT_EQ(ep["images_registered"], 16);
  // The rotations as good as calibrated. Measured (each re-linearisation triangulates from
  // the previous pass's points): 0.2149 / 0.2499 deg (Sim3 / rel) against 0.2108 / 0.2286
  // calibrated, 1.02x / 1.09x.
  EXPECT_LT(ep["rot_err_deg_median"].get<double>(), 1.05 * ec["rot_err_deg_median"].get<double>());
  EXPECT_LT(ep["rel_rot_err_deg_median"].get<double>(), 1.12 * ec["rel_rot_err_deg_median"].get<double>());
  const auto [model, est] = FirstCamera(dir_ / "prior" / "sparse" / "cameras.txt");
  const auto [gt_model, gt] = FirstCamera(data_ / "cameras.txt");
  ASSERT_EQ(model, "PINHOLE");
  EXPECT_LT(std::abs(est[0] / gt[0] - 1.0), 0.01);  // fx: measured 0.08-0.36% (above)
  EXPECT_LT(std::abs(est[1] / gt[1] - 1.0), 0.01);  // fy
  EXPECT_NEAR(est[1] / est[0], gt[1] / gt[0], 1e-5);  // the prior's ratio (its file rounds to 6 digits)
  const nlohmann::json& f = prior["intrinsics"][0]["params"];
  ASSERT_EQ(f.size(), 1u);  // one focal unknown, the principal point held
  EXPECT_EQ(f[0]["name"], "fx (fy / fx held)");
  EXPECT_GT(f[0]["stddev"].get<double>(), 0.0);
  EXPECT_LT(f[0]["stddev"].get<double>(), 0.03 * gt[0]);  // measured ~19 px, 1.2%

  // No calibration at all (focal guess 768 px, 2x short; principal point estimated in the first
  // pass). This self-calibration is bimodal and the RANSAC seed of the verification picks the
  // mode (bench/verification_seed_spread.sh): principal point x 298-301 px (the dataset's
  // 302.3), 0.22-0.37 deg, focal +1.3%; or x 277-281 px, k1 ~-0.22, 0.86-1.14 deg, focal +2.0%
  // (measured over seeds 0-3). What holds in both modes is asserted; a rotation bar of 1.3x the
  // calibrated run is not met robustly on this ring without any calibration.
  const nlohmann::json uncal = Run("uncalibrated", "");
  const nlohmann::json& eu = uncal["evaluation"];
  std::cout << "uncalibrated: " << eu["images_registered"] << "/16, focal " << 100 * FocalError("uncalibrated")
            << "%, rot err " << eu["rot_err_deg_median"] << ", rel " << eu["rel_rot_err_deg_median"] << "\n";
  EXPECT_EQ(eu["images_registered"], 16);
  EXPECT_LT(std::abs(FocalError("uncalibrated")), 0.025);  // from a guess 50% short
  EXPECT_LT(eu["rot_err_deg_median"].get<double>(), 1.3);
}

}  // namespace
