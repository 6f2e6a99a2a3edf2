#include "modules/synthetic/procedural_texture.h"
#include "pgba/io/option_ranges.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <string>

namespace pgba::synthetic {
namespace {

// Value noise of one octave: a (w/cell + 4) x (h/cell + 4) grid of uniform values in
// [-1, 1], bicubically upsampled by `cell` and cropped at a random offset so that octaves do
// not share grid lines. `channels` 1 (luminance) or 3 (chroma).
cv::Mat NoiseOctave(int width, int height, int cell, int channels, cv::RNG& rng) {
  const int gw = width / cell + 4, gh = height / cell + 4;
  cv::Mat grid(gh, gw, CV_32FC(channels));
  rng.fill(grid, cv::RNG::UNIFORM, cv::Scalar::all(-1.0), cv::Scalar::all(1.0));
  cv::Mat up;
  cv::resize(grid, up, cv::Size(gw * cell, gh * cell), 0, 0, cv::INTER_CUBIC);
  const int ox = rng.uniform(0, cell), oy = rng.uniform(0, cell);
  return up(cv::Rect(ox + cell, oy + cell, width, height)).clone();
}

cv::Scalar RandomColour(cv::RNG& rng) { return cv::Scalar(rng.uniform(0, 256), rng.uniform(0, 256), rng.uniform(0, 256)); }

int PoissonLikeCount(double mean, cv::RNG& rng) {
  // mean +- 10%: the density matters, not the exact count.
  return std::max(0, static_cast<int>(std::lround(mean * rng.uniform(0.9, 1.1))));
}

std::string RandomString(cv::RNG& rng) {
  static const char kChars[] = "ABCDEFGHJKLMNPQRSTUVWXYZabcdefghijkmnopqrstuvwxyz0123456789#%&@";
  const int n = rng.uniform(3, 11);
  std::string s;
  for (int i = 0; i < n; ++i) s += kChars[rng.uniform(0, static_cast<int>(sizeof(kChars) - 1))];
  return s;
}

}  // namespace

cv::Mat MakeProceduralTexture(int width, int height, uint64_t seed, const ProceduralTextureOptions& options) {
  CV_Assert(width >= 1 && height >= 1);
  // cv::RNG maps a zero state to a fixed constant; mixing keeps neighbouring seeds unrelated.
  cv::RNG rng(seed * 0x9E3779B97F4A7C15ULL + 0x632BE59BD9B4E019ULL);

  // 1. Multi-scale noise around a random base colour. Amplitude ~ cell^0.3: much flatter than
  //    natural 1/f so that fine octaves still give DoG extrema at the small SIFT scales.
  cv::Mat noise = cv::Mat::zeros(height, width, CV_32FC3);
  double total_amplitude = 0.0;
  for (int cell = std::max(4, options.largest_cell); cell >= 4; cell /= 2) {
    const double a = std::pow(static_cast<double>(cell), 0.3);
    cv::Mat lum = NoiseOctave(width, height, cell, 1, rng);
    cv::Mat lum3;
    cv::merge(std::vector<cv::Mat>{lum, lum, lum}, lum3);
    noise += a * lum3;
    noise += (0.35 * a) * NoiseOctave(width, height, cell, 3, rng);
    total_amplitude += a;
  }
  const cv::Scalar base(rng.uniform(70, 186), rng.uniform(70, 186), rng.uniform(70, 186));
  // A sum of uniform octaves has a standard deviation of about 0.4 x its total amplitude:
  // scaled to ~45 grey levels about the base colour (saturating at 0 and 255).
  cv::Mat shaded = noise * (110.0 / total_amplitude) + base;
  cv::Mat texture;
  shaded.convertTo(texture, CV_8UC3);

  const double area_10k = width * static_cast<double>(height) / 1e4;
  // 2. Ellipses, filled or outlined, drawn on a copy and blended back at 65%: the noise
  //    shows through, so large blobs are not flat areas without features.
  cv::Mat layer = texture.clone();
  const double log_min = std::log(options.min_blob), log_max = std::log(options.max_blob);
  for (int i = 0, n = PoissonLikeCount(options.blobs_per_10k * area_10k, rng); i < n; ++i) {
    const cv::Point centre(rng.uniform(0, width), rng.uniform(0, height));
    const cv::Size axes(static_cast<int>(std::exp(rng.uniform(log_min, log_max))),
                        static_cast<int>(std::exp(rng.uniform(log_min, log_max))));
    const int thickness = rng.uniform(0.0, 1.0) < 0.7 ? cv::FILLED : rng.uniform(1, 4);
    cv::ellipse(layer, centre, axes, rng.uniform(0.0, 180.0), 0.0, 360.0, RandomColour(rng), thickness, cv::LINE_AA);
  }
  cv::addWeighted(layer, 0.65, texture, 0.35, 0.0, texture);
  // 3. Text-like strings.
  static const int kFonts[] = {cv::FONT_HERSHEY_SIMPLEX,      cv::FONT_HERSHEY_DUPLEX, cv::FONT_HERSHEY_COMPLEX,
                               cv::FONT_HERSHEY_TRIPLEX,      cv::FONT_HERSHEY_PLAIN,  cv::FONT_HERSHEY_SCRIPT_SIMPLEX,
                               cv::FONT_HERSHEY_COMPLEX_SMALL};
  for (int i = 0, n = PoissonLikeCount(options.texts_per_10k * area_10k, rng); i < n; ++i) {
    const std::string s = RandomString(rng);
    const int font = kFonts[rng.uniform(0, static_cast<int>(std::size(kFonts)))];
    const double scale = std::exp(rng.uniform(std::log(0.4), std::log(2.5)));
    const int thickness = rng.uniform(1, 4);
    const cv::Point origin(rng.uniform(-40, width), rng.uniform(0, height + 20));
    cv::putText(texture, s, origin, font, scale, RandomColour(rng), thickness, cv::LINE_AA);
  }
  // 4. Line segments.
  for (int i = 0, n = PoissonLikeCount(options.lines_per_10k * area_10k, rng); i < n; ++i) {
    const cv::Point a(rng.uniform(0, width), rng.uniform(0, height));
    const double len = rng.uniform(10.0, 150.0), angle = rng.uniform(0.0, CV_PI);
    const cv::Point b(a.x + static_cast<int>(len * std::cos(angle)), a.y + static_cast<int>(len * std::sin(angle)));
    cv::line(texture, a, b, RandomColour(rng), rng.uniform(1, 5), cv::LINE_AA);
  }
  if (options.blur_sigma > 0) cv::GaussianBlur(texture, texture, cv::Size(0, 0), options.blur_sigma);
  return texture;
}

std::string ProceduralTextureOptions::Check() const {
  const std::string m = CheckRangesAt({{"largest_cell", largest_cell}, {"blobs_per_10k", blobs_per_10k},
                                       {"texts_per_10k", texts_per_10k}, {"lines_per_10k", lines_per_10k},
                                       {"min_blob", min_blob}, {"max_blob", max_blob}, {"blur_sigma", blur_sigma}},
                                      "ProceduralTextureOptions");
  if (!m.empty()) return m;
  if (max_blob < min_blob) return "max_blob: must be >= min_blob";
  return "";
}

}  // namespace pgba::synthetic
