// Which camera parameters the adjustments estimate (intrinsics.h): COLMAP's layouts and
// switches, and the principal point of a camera without any calibration.
#include <gtest/gtest.h>

#include <memory>

#include "pgba/optim/intrinsics.h"

namespace pgba {
namespace {

Camera MakeCamera(CameraModel model, bool has_prior_focal_length) {
  Camera c;
  c.model = model;
  c.width = 640;
  c.height = 480;
  c.params.assign(CameraModelNumParams(model), 0.0);
  c.params[0] = 768.0;
  c.has_prior_focal_length = has_prior_focal_length;
  return c;
}

TEST(Intrinsics, FreeIndicesFollowColmapsLayoutsAndSwitches) {
  const IntrinsicsOptions defaults;  // focal and distortion, principal point held
  EXPECT_EQ(FreeIntrinsicIndices(CameraModel::kSimpleRadial, defaults), (std::vector<int>{0, 3}));
  // Two-focal models: one focal unknown (fx, moving fy with it) unless the aspect ratio is free.
  EXPECT_EQ(FreeIntrinsicIndices(CameraModel::kPinhole, defaults), (std::vector<int>{0}));
  EXPECT_EQ(FreeIntrinsicIndices(CameraModel::kOpenCV, defaults), (std::vector<int>{0, 4, 5, 6, 7}));
  IntrinsicsOptions aspect = defaults;
  aspect.refine_aspect_ratio = true;
  EXPECT_EQ(FreeIntrinsicIndices(CameraModel::kPinhole, aspect), (std::vector<int>{0, 1}));
  EXPECT_EQ(FreeIntrinsicIndices(CameraModel::kOpenCV, aspect), (std::vector<int>{0, 1, 4, 5, 6, 7}));
  EXPECT_EQ(FreeIntrinsicIndices(CameraModel::kSimpleRadial, aspect), (std::vector<int>{0, 3}));
  IntrinsicsOptions pp = defaults;
  pp.refine_principal_point = true;
  EXPECT_EQ(FreeIntrinsicIndices(CameraModel::kRadial, pp), (std::vector<int>{0, 1, 2, 3, 4}));
  EXPECT_STREQ(IntrinsicParamName(CameraModel::kRadial, 2), "cy");
}

TEST(Intrinsics, ACameraWithoutCalibrationAlsoEstimatesItsPrincipalPoint) {
  const std::map<uint32_t, Camera> cameras = {{1, MakeCamera(CameraModel::kSimpleRadial, false)},   // the guess
                                              {2, MakeCamera(CameraModel::kSimpleRadial, true)}};   // a prior
  IntrinsicsOptions options;
  FreeIntrinsics free = SelectFreeIntrinsics(cameras, options);
  EXPECT_EQ(free.at(1), (std::vector<int>{0, 1, 2, 3}));
  EXPECT_EQ(free.at(2), (std::vector<int>{0, 3}));
  options.refine_principal_point_without_calibration = false;  // COLMAP's behaviour
  free = SelectFreeIntrinsics(cameras, options);
  EXPECT_EQ(free.at(1), (std::vector<int>{0, 3}));
  options.refine_focal_length = options.refine_extra_params = false;
  EXPECT_TRUE(SelectFreeIntrinsics(cameras, options).empty());
}

// The held aspect ratio: the focal unknown moves fx by 1 and fy by fy / fx, in the directions,
// in Scatter and on the manifold, and every other unknown only its own parameter.
TEST(Intrinsics, TheFocalUnknownOfATwoFocalModelHoldsTheAspectRatio) {
  Camera c = MakeCamera(CameraModel::kOpenCV, true);
  c.params = {800.0, 808.0, 320.0, 240.0, -0.05, 0.01, 0.0, 0.0};
  const std::vector<int> free = FreeIntrinsicIndices(c.model, IntrinsicsOptions());  // fx, k1, k2, p1, p2
  const Eigen::MatrixXd d = IntrinsicDirections(c, free);
  ASSERT_EQ(d.rows(), 8);
  ASSERT_EQ(d.cols(), 5);
  Eigen::MatrixXd expected = Eigen::MatrixXd::Zero(8, 5);
  expected(0, 0) = 1.0;
  expected(1, 0) = 808.0 / 800.0;
  for (int j = 1; j < 5; ++j) expected(3 + j, j) = 1.0;
  EXPECT_EQ(d, expected);

  Eigen::VectorXd v = GatherIntrinsics(c, free);
  EXPECT_EQ(v(0), 800.0);
  v(0) = 880.0;  // +10%
  v(1) = -0.08;
  Camera moved = c;
  ScatterIntrinsics(v, free, &moved);
  EXPECT_DOUBLE_EQ(moved.params[0], 880.0);
  EXPECT_DOUBLE_EQ(moved.params[1], 888.8);  // the ratio 1.01 held
  EXPECT_EQ(moved.params[2], 320.0);         // principal point not an unknown
  EXPECT_EQ(moved.params[4], -0.08);

  // The manifold moves the block the same way, and Minus inverts Plus.
  std::unique_ptr<ceres::Manifold> m(IntrinsicsManifold(c, free));
  ASSERT_TRUE(m);
  EXPECT_EQ(m->AmbientSize(), 8);
  EXPECT_EQ(m->TangentSize(), 5);
  const double delta[5] = {80.0, -0.03, 0.0, 0.0, 0.0};
  std::vector<double> plus(8);
  ASSERT_TRUE(m->Plus(c.params.data(), delta, plus.data()));
  for (int i = 0; i < 8; ++i) EXPECT_DOUBLE_EQ(plus[i], moved.params[i]) << i;
  double back[5];
  ASSERT_TRUE(m->Minus(plus.data(), c.params.data(), back));
  for (int j = 0; j < 5; ++j) EXPECT_NEAR(back[j], delta[j], 1e-12) << j;

  // fx and fy apart: each its own unit direction, fy untouched by fx's unknown.
  IntrinsicsOptions apart;
  apart.refine_aspect_ratio = true;
  const Eigen::MatrixXd d2 = IntrinsicDirections(c, FreeIntrinsicIndices(c.model, apart));
  EXPECT_EQ(d2(1, 0), 0.0);
  EXPECT_EQ(d2(1, 1), 1.0);
}

}  // namespace
}  // namespace pgba
