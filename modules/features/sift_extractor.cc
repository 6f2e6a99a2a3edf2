#include "features/sift_extractor.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <string>

#include "features/pgba_sift.h"
#include "pgba/io/option_ranges.h"
#include "pgba/util/error.h"
#include "pgba/util/text_format.h"

namespace pgba {
namespace {

constexpr double kOpenCvUpsampleBias = 0.25;

// Quantises one float descriptor row to uint8 as COLMAP stores descriptors.
void QuantiseRow(const float* in, bool root_sift, uint8_t* out) {
  float v[kSiftDescriptorSize];
  std::copy(in, in + kSiftDescriptorSize, v);
  if (root_sift) {
    // RootSIFT: L1-normalise, then element-wise sqrt; the result has unit L2 norm, so the
    // Euclidean distance between RootSIFT vectors is the Hellinger distance of the SIFTs.
    const double l1 =
        std::accumulate(v, v + kSiftDescriptorSize, 0.0, [](double s, float x) { return s + std::abs(x); });
    const float inv = l1 > 0 ? static_cast<float>(1.0 / l1) : 0.f;
    for (float& x : v) x = 512.f * std::sqrt(std::abs(x) * inv);
  }
  for (int k = 0; k < kSiftDescriptorSize; ++k)
    out[k] = static_cast<uint8_t>(std::min(255.f, std::max(0.f, std::round(v[k]))));
}

}  // namespace

double DetectionScale(int width, int height, const SiftOptions& options) {
  const int max_side = std::max(width, height);
  if (options.max_image_size <= 0 || max_side <= options.max_image_size) return 1.0;
  return static_cast<double>(max_side) / options.max_image_size;
}

std::string SiftOptions::Check() const {
  if (const std::string m = CheckRanges(*this, "features.sift"); !m.empty()) return m;
  if (implementation != "auto" && implementation != "pgba" && implementation != "opencv")
    return "implementation = \"" + implementation + "\": must be \"auto\", \"pgba\" or \"opencv\"";
  if (target_features > 0 && min_contrast_threshold > contrast_threshold)
    return "min_contrast_threshold = " + std::to_string(min_contrast_threshold) + ": must not exceed contrast_threshold (" +
           std::to_string(contrast_threshold) + ")";
  return "";
}

SiftOptions SiftOptionsForImage(const SiftOptions& options, int width, int height) {
  SiftOptions o = options;
  if (o.implementation == "auto") {
    const double scale = DetectionScale(width, height, options);
    const double megapixels = 1e-6 * width * height / (scale * scale);
    o.implementation = megapixels >= kAutoPgbaSiftMinMegapixels ? "pgba" : "opencv";
  }
  return o;
}

FeatureSet ExtractSift(const cv::Mat& gray, const SiftOptions& requested) {
  CV_Assert(gray.type() == CV_8UC1);
  if (const std::string problem = requested.Check(); !problem.empty())
    throw InputError("features.sift." + problem);
  const SiftOptions options = SiftOptionsForImage(requested, gray.cols, gray.rows);
  FeatureSet out;
  out.width = gray.cols;
  out.height = gray.rows;

  // Downscale very large images; fx, fy map downscaled pixels back to full resolution.
  cv::Mat work = gray;
  double fx = 1.0, fy = 1.0;
  const int max_side = std::max(gray.cols, gray.rows);
  if (options.max_image_size > 0 && max_side > options.max_image_size) {
    const double s = static_cast<double>(options.max_image_size) / max_side;
    const int w = std::max(1, static_cast<int>(std::lround(gray.cols * s)));
    const int h = std::max(1, static_cast<int>(std::lround(gray.rows * s)));
    cv::resize(gray, work, cv::Size(w, h), 0, 0, cv::INTER_AREA);
    fx = static_cast<double>(gray.cols) / w;
    fy = static_cast<double>(gray.rows) / h;
  }

  // OpenCV 4.6 always doubles the image and starts the scale space there (first octave -1).
  // To start at the image's own resolution instead (first octave 0), it is given the image
  // halved by 2x2 box averaging: its doubled copy is back on the full grid, and its first
  // octave approximates the full image's octave 0 (blur ~1.6-1.7 px instead of 1.6: the box,
  // the bilinear doubling and OpenCV's sqrt(1.6^2 - 1^2) px; frequencies above a quarter
  // cycle per pixel, which the sigma 1.6 blur suppresses to < 5% anyway, are lost).
  const bool own = options.implementation == "pgba";
  if (options.first_octave == 0 && !own) {
    cv::Mat half;
    cv::resize(work, half, cv::Size((work.cols + 1) / 2, (work.rows + 1) / 2), 0, 0, cv::INTER_AREA);
    work = half;
    fx = static_cast<double>(gray.cols) / work.cols;
    fy = static_cast<double>(gray.rows) / work.rows;
  }

  std::vector<cv::KeyPoint> kps;
  cv::Mat desc;
  double contrast = options.contrast_threshold;
  for (;;) {
    kps.clear();
    if (own) {
      PgbaSiftParams params;
      params.upsample = options.first_octave == -1;
      params.contrast_threshold = contrast;
      params.edge_threshold = options.edge_threshold;
      params.max_features = options.max_features;
      DetectAndDescribePgbaSift(work, params, &kps, &desc);
    } else {
      cv::Ptr<cv::SIFT> sift =
          cv::SIFT::create(options.max_features, 3, contrast, options.edge_threshold, 1.6, CV_32F);
      sift->detectAndCompute(work, cv::noArray(), kps, desc);
    }
    if (options.target_features <= 0 || static_cast<int>(kps.size()) >= options.target_features ||
        contrast / 2 < options.min_contrast_threshold)
      break;
    contrast /= 2;
  }
  out.contrast_threshold = static_cast<float>(contrast);

  // Strongest first, ties broken by position: a deterministic order independent of how
  // OpenCV's parallel detection happened to interleave.
  std::vector<int> order(kps.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    const cv::KeyPoint& ka = kps[a];
    const cv::KeyPoint& kb = kps[b];
    if (ka.response != kb.response) return ka.response > kb.response;
    if (ka.pt.y != kb.pt.y) return ka.pt.y < kb.pt.y;
    if (ka.pt.x != kb.pt.x) return ka.pt.x < kb.pt.x;
    if (ka.size != kb.size) return ka.size < kb.size;
    return ka.angle < kb.angle;
  });
  if (options.max_features > 0 && static_cast<int>(order.size()) > options.max_features)
    order.resize(options.max_features);

  out.keypoints.resize(order.size());
  out.descriptors.create(static_cast<int>(order.size()), kSiftDescriptorSize, CV_8U);
  const double mean_f = 0.5 * (fx + fy);
  // Both implementations double the image the same way; pgba's without doubling has no bias.
  const double bias = own && options.first_octave == 0 ? 0.0 : kOpenCvUpsampleBias;
  for (size_t i = 0; i < order.size(); ++i) {
    const cv::KeyPoint& kp = kps[order[i]];
    Keypoint& k = out.keypoints[i];
    // OpenCV puts pixel centres at integers, COLMAP at +0.5: shift, then scale the
    // downscaled image's extent onto the full image's extent. OpenCV 4.6's SIFT also
    // detects on a 2x upsampled image (INTER_LINEAR_EXACT: upsampled pixel u samples the
    // input at u/2 - 0.25) but maps keypoints back with u/2 alone, a +0.25 px bias that
    // is removed here (kOpenCvUpsampleBias; the unit test locates a blob to 0.05 px).
    k.x = static_cast<float>((kp.pt.x - bias + 0.5) * fx);
    k.y = static_cast<float>((kp.pt.y - bias + 0.5) * fy);
    k.scale = static_cast<float>(0.5 * kp.size * mean_f);
    k.orientation = static_cast<float>(kp.angle * CV_PI / 180.0);
    QuantiseRow(desc.ptr<float>(order[i]), options.root_sift, out.descriptors.ptr<uint8_t>(static_cast<int>(i)));
  }
  return out;
}

std::string SiftOptionsKey(const SiftOptions& options) {
  std::ostringstream s;
  // The OpenCV implementation keeps the key it always had (its caches stay valid). pgba's is
  // "pgba2" since it drops duplicate keypoints as OpenCV does: a cache written before holds
  // them, and is recomputed instead of reused.
  const std::string impl = options.implementation == "pgba" ? "pgba2" : options.implementation;
  s << "sift1" << (options.implementation == "opencv" ? "" : " impl=" + impl) << " n=" << options.max_features << " root=" << options.root_sift << " max=" << options.max_image_size
    << " c=" << options.contrast_threshold << " e=" << options.edge_threshold
    << (options.first_octave == -1 ? "" : " o=" + std::to_string(options.first_octave))
    << (options.target_features <= 0
            ? ""
            : " t=" + std::to_string(options.target_features) + " cmin=" + FormatNumber("%g", options.min_contrast_threshold));
  return s.str();
}

}  // namespace pgba
