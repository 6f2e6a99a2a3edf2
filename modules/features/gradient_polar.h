// Gradient samples to polar form, 8 at a time: the inner step of SIFT's orientation
// histograms and descriptors, where one atan2 and one sqrt per sample of every window were
// most of the time.
#pragma once

#include <cstddef>
#include <vector>

namespace pgba {

// For k in [0, n): deg[k] = FastAtan2Degrees(dy[k], dx[k]) (fast_atan2.h) and
// mag[k] = sqrt(dx[k]^2 + dy[k]^2) * weight[k], with the same float operations in the same
// order as those scalar expressions, so the same bits. Reads and writes whole groups of 8:
// every array must hold n rounded up to a multiple of 8 floats.
void GradientsToPolar(const float* dx, const float* dy, const float* weight, int n, float* deg, float* mag);

// The samples of one window (an orientation histogram's or a descriptor's), in the order
// their sums are taken: filled up to some n, then ToPolar(n).
struct GradientSamples {
  std::vector<float> dx, dy, weight, deg, mag;
  // Room for n samples (and the rounding up to groups of 8); keeps what is there.
  void Reserve(int n) {
    const std::size_t size = static_cast<std::size_t>(n) + 8;
    if (dx.size() >= size) return;
    for (std::vector<float>* v : {&dx, &dy, &weight, &deg, &mag}) v->resize(size);
  }
  void ToPolar(int n) { GradientsToPolar(dx.data(), dy.data(), weight.data(), n, deg.data(), mag.data()); }
};

}  // namespace pgba
