// The 1-D factor of a separable Gaussian window: g[k] = exp(k^2 c) for k = 0..radius, so that
// exp((i^2 + j^2) c) = g[i] g[j] and a window costs one exp per offset instead of one per
// sample (the orientation histogram and the descriptor both weight their samples so).
#pragma once

#include <cmath>
#include <vector>

namespace pgba {

class SeparableGaussian {
 public:
  // c = exp_per_px2 (negative): -1 / (2 sigma^2) in the window's pixel units.
  SeparableGaussian(int radius, float exp_per_px2) {
    if (radius + 1 > kOnStack) {
      heap_.resize(radius + 1);
      g_ = heap_.data();
    }
    for (int k = 0; k <= radius; ++k) g_[k] = std::exp(static_cast<float>(k * k) * exp_per_px2);
  }
  SeparableGaussian(const SeparableGaussian&) = delete;  // g_ may point into this object
  SeparableGaussian& operator=(const SeparableGaussian&) = delete;

  float operator[](int k) const { return g_[k]; }

 private:
  // Offsets held without an allocation: the windows of every usual keypoint scale.
  static constexpr int kOnStack = 256;
  float stack_[kOnStack];
  std::vector<float> heap_;
  float* g_ = stack_;
};

}  // namespace pgba
