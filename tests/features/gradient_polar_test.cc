// GradientsToPolar (8 samples at a time) against the scalar expressions it replaces in the
// orientation histograms and descriptors, bit for bit, and against std::atan2 and std::hypot.
#include "features/gradient_polar.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "features/fast_atan2.h"

namespace pgba {
namespace {

uint32_t Bits(float v) {
  uint32_t b;
  std::memcpy(&b, &v, sizeof(b));
  return b;
}

TEST(GradientPolar, SameBitsAsTheScalarFormulasAndCloseToLibm) {
  // Gradients as SIFT sees them (differences of grey levels 0..255), and the corner cases
  // of the branches: zeros of either sign, equal legs, each quadrant and axis.
  std::vector<float> dx, dy, w;
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> grey(-255.f, 255.f), weight(0.f, 1.f);
  for (int i = 0; i < 10003; ++i) {
    dx.push_back(grey(rng));
    dy.push_back(grey(rng));
    w.push_back(weight(rng));
  }
  const float special[] = {0.f, -0.f, 1.f, -1.f, 3.5f, -3.5f, 1e-30f, -1e-30f};
  for (float x : special)
    for (float y : special) {
      dx.push_back(x);
      dy.push_back(y);
      w.push_back(0.5f);
    }
  const int n = static_cast<int>(dx.size());  // not a multiple of 8: the last group is partial
  ASSERT_NE(n % 8, 0);
  for (std::vector<float>* v : {&dx, &dy, &w}) v->resize(n + 8, 0.f);
  std::vector<float> deg(n + 8), mag(n + 8);
  GradientsToPolar(dx.data(), dy.data(), w.data(), n, deg.data(), mag.data());
  for (int k = 0; k < n; ++k) {
    ASSERT_EQ(Bits(deg[k]), Bits(FastAtan2Degrees(dy[k], dx[k]))) << dx[k] << " " << dy[k];
    ASSERT_EQ(Bits(mag[k]), Bits(std::sqrt(dx[k] * dx[k] + dy[k] * dy[k]) * w[k])) << dx[k] << " " << dy[k];
    ASSERT_GE(deg[k], 0.f);
    ASSERT_LT(deg[k], 360.f);
    if (dx[k] == 0.f && dy[k] == 0.f) continue;
    // The polynomial's error, ~1e-5 rad, in degrees; the angle wraps at 360.
    double truth = std::atan2(static_cast<double>(dy[k]), static_cast<double>(dx[k])) * 180.0 / M_PI;
    if (truth < 0) truth += 360.0;
    const double diff = std::remainder(deg[k] - truth, 360.0);
    EXPECT_LT(std::abs(diff), 1e-3) << dx[k] << " " << dy[k];
    EXPECT_NEAR(mag[k], std::hypot(static_cast<double>(dx[k]), static_cast<double>(dy[k])) * w[k],
                1e-6 * (1 + mag[k]));
  }
}

}  // namespace
}  // namespace pgba
