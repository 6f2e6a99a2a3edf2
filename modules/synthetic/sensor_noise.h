// Sensor noise of rendered photographs: Gaussian noise of `sigma` grey levels added to each
// 8-bit channel, rounded and saturated. Also keeps SIFT from locking onto perfectly flat
// regions. The noise is a function of `seed` alone (cv::RNG), so images are reproducible.
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>

namespace pgba::synthetic {

// In place on a CV_8UC3 image; sigma 0 leaves it untouched.
void AddSensorNoise(cv::Mat* image, double sigma, uint64_t seed);

}  // namespace pgba::synthetic
