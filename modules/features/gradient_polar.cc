#include "features/gradient_polar.h"

#include "features/vec8.h"

namespace pgba {
namespace {

// Inline only, no vector crosses a call boundary; GCC reports it at the end of the file.
#pragma GCC diagnostic ignored "-Wpsabi"
using simd::Abs8;
using simd::Load8;
using simd::Splat8;
using simd::Sqrt8;
using simd::Store8;
using simd::Vec8;
using simd::Vec8i;

// FastAtan2Degrees (fast_atan2.h) on 8 lanes: its branches as selects, its arithmetic as is.
inline __attribute__((always_inline)) Vec8 Atan2Degrees8(Vec8 y, Vec8 x) {
  const Vec8 ax = Abs8(x), ay = Abs8(y);
  const Vec8i swap = ay > ax;
  const Vec8 z = (swap ? ax : ay) / (swap ? ay : ax);
  const Vec8 z2 = z * z;
  Vec8 a = z * (0.99997726f +
                z2 * (-0.33262347f + z2 * (0.19354346f + z2 * (-0.11643287f + z2 * (0.05265332f + z2 * -0.01172120f)))));
  a *= 57.29577951308232f;
  a = swap ? Splat8(90.f) - a : a;
  a = x < 0.f ? Splat8(180.f) - a : a;
  a = y < 0.f ? Splat8(360.f) - a : a;
  a = a >= 360.f ? a - 360.f : a;
  return (ax == 0.f) & (ay == 0.f) ? Splat8(0.f) : a;
}

}  // namespace

PGBA_MULTIVERSION
void GradientsToPolar(const float* dx, const float* dy, const float* weight, int n, float* deg, float* mag) {
  for (int k = 0; k < n; k += 8) {
    const Vec8 x = Load8(dx + k), y = Load8(dy + k);
    Store8(mag + k, Sqrt8(x * x + y * y) * Load8(weight + k));
    Store8(deg + k, Atan2Degrees8(y, x));
  }
}

}  // namespace pgba
