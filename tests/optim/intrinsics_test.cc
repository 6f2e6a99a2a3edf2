// Which camera parameters the adjustments estimate (intrinsics.h): COLMAP's layouts and
// switches, and the principal point of a camera without any calibration.
#include <gtest/gtest.h>

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
  EXPECT_EQ(FreeIntrinsicIndices(CameraModel::kPinhole, defaults), (std::vector<int>{0, 1}));
  EXPECT_EQ(FreeIntrinsicIndices(CameraModel::kOpenCV, defaults), (std::vector<int>{0, 1, 4, 5, 6, 7}));
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

}  // namespace
}  // namespace pgba
