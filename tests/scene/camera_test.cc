// COLMAP camera models: projection and undistortion are inverse over the whole image, the
// templated (autodiff) projection equals the double one and has the right derivatives,
// parameter validation and model names.
#include "pgba/scene/camera.h"

#include <ceres/jet.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <random>

namespace pgba {
namespace {

const CameraModel kAllModels[] = {CameraModel::kSimplePinhole, CameraModel::kPinhole, CameraModel::kSimpleRadial,
                                  CameraModel::kRadial, CameraModel::kOpenCV};

// Realistic calibrations of a 1920x1080 camera with a ~87 degree diagonal field of view
// (strong enough distortion to matter at the corners: tens of pixels).
Camera MakeCamera(CameraModel model) {
  Camera c;
  c.camera_id = 7;
  c.model = model;
  c.width = 1920;
  c.height = 1080;
  switch (model) {
    case CameraModel::kSimplePinhole: c.params = {1000, 960, 540}; break;
    case CameraModel::kPinhole: c.params = {1000, 1012, 955.5, 547.25}; break;
    case CameraModel::kSimpleRadial: c.params = {1000, 960, 540, -0.12}; break;
    case CameraModel::kRadial: c.params = {1000, 962, 538, -0.15, 0.04}; break;
    case CameraModel::kOpenCV: c.params = {1000, 1012, 955.5, 547.25, -0.15, 0.04, 0.002, -0.001}; break;
  }
  return c;
}

class CameraModelTest : public ::testing::TestWithParam<CameraModel> {};

// Every pixel of a dense grid over the whole image (edges and corners included):
// PixelToBearing then Project returns the pixel to 1e-9 px.
TEST_P(CameraModelTest, PixelToBearingThenProjectOverWholeImage) {
  const Camera cam = MakeCamera(GetParam());
  ASSERT_EQ(cam.Validate(), "");
  double worst = 0.0;
  for (int i = 0; i <= 48; ++i) {
    for (int j = 0; j <= 27; ++j) {
      const Eigen::Vector2d px(cam.width * i / 48.0, cam.height * j / 27.0);
      const Eigen::Vector3d b = cam.PixelToBearing(px);
      ASSERT_NEAR(b.norm(), 1.0, 1e-15);
      ASSERT_GT(b.z(), 0.0);
      worst = std::max(worst, (cam.Project(b) - px).norm());
      // The normalised coordinates are the bearing's (x/z, y/z), independent of depth.
      const Eigen::Vector2d n = cam.PixelToNormalized(px);
      EXPECT_LT((n - b.head<2>() / b.z()).norm(), 1e-15);
      EXPECT_LT((cam.Project(7.5 * b) - px).norm(), 1e-9);
    }
  }
  EXPECT_LT(worst, 1e-9) << CameraModelName(GetParam());
}

// Points in front of the camera that land in the image: Project then PixelToBearing gives
// the point's direction to 1e-12 rad.
TEST_P(CameraModelTest, ProjectThenPixelToBearing) {
  const Camera cam = MakeCamera(GetParam());
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-1.0, 1.0), depth(0.5, 100.0);
  int inside = 0;
  for (int trial = 0; trial < 5000; ++trial) {
    const Eigen::Vector3d X = depth(rng) * Eigen::Vector3d(u(rng), 0.6 * u(rng), 1.0);
    const Eigen::Vector2d px = cam.Project(X);
    if (px.x() < 0 || px.y() < 0 || px.x() > cam.width || px.y() > cam.height) continue;
    ++inside;
    const Eigen::Vector3d b = cam.PixelToBearing(px);
    EXPECT_LT(std::atan2(b.cross(X.normalized()).norm(), b.dot(X.normalized())), 1e-12);
  }
  EXPECT_GT(inside, 2000);
}

// Distortion actually does something for the distorted models (so the round trips above
// are not trivially identities), and nothing for the pinhole ones.
TEST_P(CameraModelTest, DistortionMagnitude) {
  const Camera cam = MakeCamera(GetParam());
  double u = 0.9, v = 0.5, ud, vd;
  DistortNormalized(cam.model, cam.params.data(), u, v, &ud, &vd);
  const double shift_px = cam.MeanFocal() * std::hypot(ud - u, vd - v);
  if (cam.model == CameraModel::kSimplePinhole || cam.model == CameraModel::kPinhole)
    EXPECT_EQ(shift_px, 0.0);
  else
    EXPECT_GT(shift_px, 20.0);
}

// The templated projection on Jets gives the double projection as its value, and its
// derivatives match central finite differences.
TEST_P(CameraModelTest, AutodiffProjectionMatchesDouble) {
  const Camera cam = MakeCamera(GetParam());
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  using Jet = ceres::Jet<double, 3>;
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::Vector3d X(u(rng), 0.6 * u(rng), 1.0 + 0.5 * (u(rng) + 1.0));
    Jet xj[3] = {Jet(X.x(), 0), Jet(X.y(), 1), Jet(X.z(), 2)};
    Jet pj[2];
    ProjectToPixel(cam.model, cam.params.data(), xj, pj);
    const Eigen::Vector2d px = cam.Project(X);
    // Equal up to rounding (Jet division multiplies by the reciprocal).
    EXPECT_NEAR(pj[0].a, px.x(), 1e-12 * std::abs(px.x()));
    EXPECT_NEAR(pj[1].a, px.y(), 1e-12 * std::abs(px.y()));
    for (int k = 0; k < 3; ++k) {
      Eigen::Vector3d d = Eigen::Vector3d::Zero();
      d(k) = 1e-6;
      const Eigen::Vector2d fd = (cam.Project(X + d) - cam.Project(X - d)) / 2e-6;
      EXPECT_NEAR(pj[0].v[k], fd.x(), 1e-5 * (1 + std::abs(fd.x())));
      EXPECT_NEAR(pj[1].v[k], fd.y(), 1e-5 * (1 + std::abs(fd.y())));
    }
  }
}

INSTANTIATE_TEST_SUITE_P(AllModels, CameraModelTest, ::testing::ValuesIn(kAllModels),
                         [](const ::testing::TestParamInfo<CameraModel>& info) {
                           return std::string(CameraModelName(info.param));
                         });

// The projection formulas against COLMAP's definitions written out by hand.
TEST(Camera, ProjectionFormulas) {
  const Eigen::Vector3d X(0.3, -0.2, 2.0);
  const double u = 0.15, v = -0.1, r2 = u * u + v * v;
  Camera c = MakeCamera(CameraModel::kSimplePinhole);
  EXPECT_LT((c.Project(X) - Eigen::Vector2d(1000 * u + 960, 1000 * v + 540)).norm(), 1e-12);
  c = MakeCamera(CameraModel::kPinhole);
  EXPECT_LT((c.Project(X) - Eigen::Vector2d(1000 * u + 955.5, 1012 * v + 547.25)).norm(), 1e-12);
  c = MakeCamera(CameraModel::kSimpleRadial);
  double f = 1 - 0.12 * r2;
  EXPECT_LT((c.Project(X) - Eigen::Vector2d(1000 * u * f + 960, 1000 * v * f + 540)).norm(), 1e-12);
  c = MakeCamera(CameraModel::kRadial);
  f = 1 - 0.15 * r2 + 0.04 * r2 * r2;
  EXPECT_LT((c.Project(X) - Eigen::Vector2d(1000 * u * f + 962, 1000 * v * f + 538)).norm(), 1e-12);
  c = MakeCamera(CameraModel::kOpenCV);
  const double p1 = 0.002, p2 = -0.001;
  const double ud = u * f + 2 * p1 * u * v + p2 * (r2 + 2 * u * u);
  const double vd = v * f + 2 * p2 * u * v + p1 * (r2 + 2 * v * v);
  EXPECT_LT((c.Project(X) - Eigen::Vector2d(1000 * ud + 955.5, 1012 * vd + 547.25)).norm(), 1e-12);
}

TEST(Camera, MeanFocal) {
  EXPECT_EQ(MakeCamera(CameraModel::kSimpleRadial).MeanFocal(), 1000.0);
  EXPECT_EQ(MakeCamera(CameraModel::kPinhole).MeanFocal(), 1006.0);
  EXPECT_EQ(MakeCamera(CameraModel::kOpenCV).MeanFocal(), 1006.0);
  EXPECT_EQ(Camera().MeanFocal(), 0.0);
}

TEST(Camera, ValidateReportsEachProblem) {
  for (CameraModel m : kAllModels) EXPECT_EQ(MakeCamera(m).Validate(), "") << CameraModelName(m);
  Camera c = MakeCamera(CameraModel::kOpenCV);
  c.params.pop_back();
  EXPECT_NE(c.Validate().find("needs 8 parameters, got 7"), std::string::npos) << c.Validate();
  c = MakeCamera(CameraModel::kSimplePinhole);
  c.params.push_back(0.1);
  EXPECT_NE(c.Validate().find("needs 3 parameters"), std::string::npos);
  c = MakeCamera(CameraModel::kPinhole);
  c.params.clear();
  EXPECT_NE(c.Validate(), "");
  c = MakeCamera(CameraModel::kRadial);
  c.params[3] = std::nan("");
  EXPECT_NE(c.Validate().find("non-finite"), std::string::npos);
  c = MakeCamera(CameraModel::kRadial);
  c.params[1] = INFINITY;
  EXPECT_NE(c.Validate().find("non-finite"), std::string::npos);
  c = MakeCamera(CameraModel::kPinhole);
  c.width = 0;
  EXPECT_NE(c.Validate().find("size"), std::string::npos);
  c = MakeCamera(CameraModel::kPinhole);
  c.height = -5;
  EXPECT_NE(c.Validate().find("size"), std::string::npos);
  c = MakeCamera(CameraModel::kSimpleRadial);
  c.params[0] = 0.0;
  EXPECT_NE(c.Validate().find("focal"), std::string::npos);
  c = MakeCamera(CameraModel::kPinhole);
  c.params[1] = -1000.0;
  EXPECT_NE(c.Validate().find("focal"), std::string::npos);
}

// SIMPLE_RADIAL k = -40 (the reported case): the distorted radius of most of the image is
// beyond the largest that r (1 + k r^2) reaches, so no ray maps there. The undistortion
// reports it and Validate refuses the calibration; realistic distortions stay valid.
TEST(Camera, NonInvertibleDistortionIsReportedAndRefused) {
  Camera c = MakeCamera(CameraModel::kSimpleRadial);
  c.params[3] = -40.0;
  Eigen::Vector2d u;
  EXPECT_TRUE(c.UndistortPixel(Eigen::Vector2d(960, 540), &u));  // the centre still maps to itself
  EXPECT_NEAR(u.norm(), 0.0, 1e-15);
  EXPECT_FALSE(c.UndistortPixel(Eigen::Vector2d(0, 0), &u));
  EXPECT_NE(c.Validate().find("distortion is not invertible over the image"), std::string::npos) << c.Validate();
  // A barrel distortion that turns round just inside the corners (r_max of 1 + k r^2 at
  // r = 1/sqrt(-3k), distorted radius 2/3 of it).
  c = MakeCamera(CameraModel::kSimpleRadial);
  const double corner = Eigen::Vector2d(960, 540).norm() / 1000;  // distorted radius of the corners
  c.params[3] = -4.0 / (27.0 * corner * corner) * 1.05;           // turning point 2.5% inside
  EXPECT_NE(c.Validate(), "");
  c.params[3] = -4.0 / (27.0 * corner * corner) * 0.9;  // turning point outside the image
  EXPECT_EQ(c.Validate(), "");
  c = MakeCamera(CameraModel::kOpenCV);
  c.params[4] = -3.0;
  EXPECT_NE(c.Validate().find("not invertible"), std::string::npos);
  for (CameraModel m : kAllModels) {
    Eigen::Vector2d v;
    EXPECT_TRUE(MakeCamera(m).UndistortPixel(Eigen::Vector2d(0, 1080), &v)) << CameraModelName(m);
  }
}

TEST(Camera, ParseCameraModel) {
  const std::pair<const char*, int> expected[] = {
      {"SIMPLE_PINHOLE", 3}, {"PINHOLE", 4}, {"SIMPLE_RADIAL", 4}, {"RADIAL", 5}, {"OPENCV", 8}};
  for (const auto& [name, n] : expected) {
    CameraModel m;
    ASSERT_TRUE(ParseCameraModel(name, &m)) << name;
    EXPECT_STREQ(CameraModelName(m), name);
    EXPECT_EQ(CameraModelNumParams(m), n);
  }
  for (const char* bad : {"", "pinhole", "FULL_OPENCV", "OPENCV_FISHEYE", "PINHOLE ", "THIN_PRISM_FISHEYE"}) {
    CameraModel m = CameraModel::kRadial;
    EXPECT_FALSE(ParseCameraModel(bad, &m)) << bad;
    EXPECT_EQ(m, CameraModel::kRadial);  // untouched on failure
  }
}

}  // namespace
}  // namespace pgba
