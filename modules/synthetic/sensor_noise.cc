#include "modules/synthetic/sensor_noise.h"

namespace pgba::synthetic {

void AddSensorNoise(cv::Mat* image, double sigma, uint64_t seed) {
  CV_Assert(image->type() == CV_8UC3);
  if (!(sigma > 0)) return;
  cv::Mat noisy(image->size(), CV_32FC3);
  cv::RNG(seed).fill(noisy, cv::RNG::NORMAL, 0.0, sigma);
  cv::Mat f32;
  image->convertTo(f32, CV_32FC3);
  noisy += f32;
  noisy.convertTo(*image, CV_8UC3);  // rounds and saturates
}

}  // namespace pgba::synthetic
