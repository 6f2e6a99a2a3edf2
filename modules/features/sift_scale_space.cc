#include "features/sift_scale_space.h"

#include <algorithm>
#include <cmath>

#include "features/gaussian_blur.h"

namespace pgba {
namespace {

// Blur that the camera is assumed to have applied already, in input pixels.
constexpr double kInitialBlur = 0.5;

}  // namespace

SiftScaleSpace BuildSiftScaleSpace(const cv::Mat& gray8u, bool upsample, const SiftOctaveCallback& on_octave,
                                   int layers_per_octave, double sigma) {
  CV_Assert(gray8u.type() == CV_8UC1 && layers_per_octave >= 1);
  SiftScaleSpace ss;
  ss.layers_per_octave = layers_per_octave;
  ss.sigma = sigma;
  ss.upsampled = upsample;
  const int s = layers_per_octave;

  // Octave 0, layer 0: blur the (doubled) image from its assumed blur up to sigma.
  cv::Mat base;
  double assumed = kInitialBlur;
  if (upsample) {
    ParallelUpsample2x(gray8u, base);
    assumed *= 2;
  } else {
    gray8u.convertTo(base, CV_32F);
  }
  const int min_side = std::min(base.rows, base.cols);
  const int num_octaves = std::max(1, static_cast<int>(std::lround(std::log2(static_cast<double>(min_side)) - 2)));

  // Incremental blurs (Lowe): layer i has total blur sigma k^i, k = 2^(1/s); layer i is
  // layer i-1 blurred by sqrt((sigma k^i)^2 - (sigma k^(i-1))^2).
  std::vector<double> increment(s + 3);
  increment[0] = std::sqrt(std::max(sigma * sigma - assumed * assumed, 0.01));
  const double k = std::pow(2.0, 1.0 / s);
  for (int i = 1; i < s + 3; ++i) {
    const double previous = std::pow(k, i - 1) * sigma;
    const double total = previous * k;
    increment[i] = std::sqrt(total * total - previous * previous);
  }

  // Views for the later octaves' layers, carved in order from ss.storage (64-byte aligned);
  // a layer that does not fit gets its own memory.
  size_t buffer = 0, offset = 0;
  auto carve = [&](int rows, int cols) {
    const size_t bytes = (static_cast<size_t>(rows) * cols * sizeof(float) + 63) / 64 * 64;
    for (; buffer < ss.storage.size(); ++buffer, offset = 0) {
      const cv::Mat& m = ss.storage[buffer];
      if (offset + bytes <= m.total() * m.elemSize()) {
        cv::Mat view(rows, cols, CV_32F, m.data + offset);
        offset += bytes;
        return view;
      }
    }
    return cv::Mat(rows, cols, CV_32F);
  };

  ss.gaussians.assign(num_octaves, std::vector<cv::Mat>(s + 3));
  for (int o = 0; o < num_octaves; ++o) {
    std::vector<cv::Mat>& g = ss.gaussians[o];
    if (o == 0) {
      ParallelGaussianBlur(base, g[0], increment[0]);
      base.release();
    } else {
      // Layer s of the previous octave has blur 2 sigma: decimated, sigma in the new pixels.
      const cv::Mat& from = ss.gaussians[o - 1][s];
      for (cv::Mat& layer : g) layer = carve(from.rows / 2, from.cols / 2);
      ParallelDecimate2x(from, g[0]);
    }
    // The DoG is not stored: the detector takes differences of these layers where it reads
    // them (6 layers per octave in memory instead of 3 Gaussians + 5 DoGs, whose fresh pages
    // were the largest cost of a 6 MP image on the project's VM).
    for (int i = 1; i < s + 3; ++i) ParallelGaussianBlur(g[i - 1], g[i], increment[i]);
    on_octave(ss, o);
    for (int i : {0, s + 1, s + 2}) {
      if (o == 0) ss.storage.push_back(g[i]);
      g[i].release();
    }
  }
  return ss;
}

}  // namespace pgba
