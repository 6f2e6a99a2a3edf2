// MaxPixelShift against closed forms: no change moves nothing; a focal scaled by s moves a
// pixel at distance r from the principal point by (s - 1) r, most at the farthest corner; a
// radial k1 added to a distortion-free lens moves the corner by r |k1| (r / f)^2; a pixel without
// a ray in the `from` lens (distortion folded over the image) gives infinity, not a number.
#include "modules/calibration/pixel_shift.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace pgba {
namespace {

Camera Radial(double f, double k, int w = 640, int h = 480) {
  Camera c;
  c.camera_id = 1;
  c.model = CameraModel::kSimpleRadial;
  c.width = w;
  c.height = h;
  c.params = {f, w / 2.0, h / 2.0, k};
  return c;
}

TEST(PixelShift, SameCameraMovesNothing) { EXPECT_NEAR(MaxPixelShift(Radial(500, -0.05), Radial(500, -0.05)), 0, 1e-9); }

TEST(PixelShift, FocalScaleMovesTheFarthestCornerMost) {
  const double r = 400.0;  // pixel (0, 0) from the principal point (320, 240)
  EXPECT_NEAR(MaxPixelShift(Radial(500, 0), Radial(550, 0)), 0.1 * r, 1e-6);
  EXPECT_NEAR(MaxPixelShift(Radial(550, 0), Radial(500, 0)), r / 11, 1e-6);
}

TEST(PixelShift, RadialDistortionAtTheCorner) {
  const double r = 400.0, f = 500.0, k = -0.02;
  EXPECT_NEAR(MaxPixelShift(Radial(f, 0), Radial(f, k)), r * std::abs(k) * (r / f) * (r / f), 1e-6);
}

TEST(PixelShift, PixelWithoutARayIsInfinity) {
  EXPECT_EQ(MaxPixelShift(Radial(300, -40), Radial(300, 0)), std::numeric_limits<double>::infinity());
}

TEST(PixelShift, CamerasOfDifferentSizesOrTooSmallAGridAreRefused) {
  EXPECT_THROW(MaxPixelShift(Radial(500, 0), Radial(500, 0, 800, 600)), std::invalid_argument);
  EXPECT_THROW(MaxPixelShift(Radial(500, 0), Radial(500, 0), 1), std::invalid_argument);
}

TEST(PixelShift, LargestOverTheCamerasInBoth) {
  std::map<uint32_t, Camera> a{{1, Radial(500, 0)}, {2, Radial(500, 0)}}, b{{2, Radial(520, 0)}, {3, Radial(900, 0)}};
  EXPECT_NEAR(MaxPixelShift(a, b), MaxPixelShift(a.at(2), b.at(2)), 1e-12);  // camera 3 is not in a
  EXPECT_EQ(MaxPixelShift(a, {}), 0.0);
}

}  // namespace
}  // namespace pgba
