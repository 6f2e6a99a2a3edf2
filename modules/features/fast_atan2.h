// atan2 in degrees, [0, 360), by a degree-11 odd minimax polynomial on [-1, 1] (error
// ~1e-5 rad, far below SIFT's 10 and 45 degree bins): std::atan2 was a sixth of pgba's SIFT
// time, called once per gradient sample of every orientation and descriptor window.
#pragma once

#include <cmath>

namespace pgba {

inline float FastAtan2Degrees(float y, float x) {
  const float ax = std::abs(x), ay = std::abs(y);
  if (ax == 0.f && ay == 0.f) return 0.f;
  // z in [0, 1]: the angle of the smaller over the larger leg, mapped back by symmetry.
  const bool swap = ay > ax;
  const float z = swap ? ax / ay : ay / ax;
  const float z2 = z * z;
  float a = z * (0.99997726f +
                 z2 * (-0.33262347f + z2 * (0.19354346f + z2 * (-0.11643287f + z2 * (0.05265332f + z2 * -0.01172120f)))));
  a *= 57.29577951308232f;
  if (swap) a = 90.f - a;
  if (x < 0) a = 180.f - a;
  if (y < 0) a = 360.f - a;
  return a >= 360.f ? a - 360.f : a;
}

}  // namespace pgba
