// SIFT detection and description, pgba's own (pgba_sift.h) or OpenCV's (cv::SIFT), with the
// options a photogrammetric front end needs: a cap on the number of features, RootSIFT
// (Arandjelovic & Zisserman 2012: Hellinger kernel = L2 on sqrt of L1-normalised SIFT) and
// downscaling of very large images.
#pragma once

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <string>

#include "features/feature_set.h"

namespace pgba {

// Detection images (after max_image_size) of at least this many megapixels get pgba's SIFT
// under implementation "auto", smaller ones OpenCV's: between the sizes measured, 0.31 MP
// (where dino_sparse_ring's weak view graph fares worse with pgba's) and 0.70 MP (as accurate).
constexpr double kAutoPgbaSiftMinMegapixels = 0.5;

struct SiftOptions {
  // Which SIFT: "opencv" (cv::SIFT of OpenCV 4.6, which builds its pyramid on one thread),
  // "pgba" (pgba_sift.h: the same algorithm with the pyramid, the extrema and the
  // descriptors parallel inside one image) or "auto" (the default): pgba's from
  // kAutoPgbaSiftMinMegapixels on, OpenCV's below. By measurement (docs/measurement_history.md "Session 18:
  // pgba's SIFT by image size", bench/sift_by_size.sh): on the Strecha sets downscaled to
  // 0.27-6.3 MP pgba's takes 0.52-0.87x OpenCV's CPU time and the final rotation errors are
  // equal within their noise (a few thousandths of a degree either way); on the 0.31 MP
  // Middlebury rings temple is equal within the verification seeds' spread (its worst image
  // no longer worse since the duplicate keypoints went), but dino_sparse_ring's weakly
  // textured ring takes in a wrong weak pair with it on 3 of 5 seeds (with OpenCV's on 1 of
  // 5), so small images keep OpenCV's.
  std::string implementation = "auto";
  // Keep at most this many keypoints (the strongest responses); COLMAP's default.
  int max_features = 8192;
  // RootSIFT descriptors (better matching at no cost); false gives plain SIFT.
  bool root_sift = true;
  // Images whose larger side exceeds this many pixels are downscaled (INTER_AREA) before
  // detection; keypoints are mapped back to full-resolution pixels. <= 0 disables.
  int max_image_size = 3200;
  // OpenCV SIFT thresholds; contrast is divided by the 3 layers per octave. Half OpenCV's
  // 0.04: weakly textured objects (Middlebury temple: ~800 features per 640x480 image at
  // 0.04) get twice the features and more verified pairs; textured images are capped by
  // max_features anyway.
  double contrast_threshold = 0.02;
  double edge_threshold = 10.0;
  // Where the scale space starts (COLMAP's first_octave): -1 on a 2x upsampled copy of the
  // image (OpenCV 4.6's only mode, COLMAP's default), 0 at the image's own resolution (pgba's
  // implementation starts there directly, OpenCV's on the image halved then doubled). 0 skips
  // the octave that holds 3/4 of the pyramid's pixels, ~8x less time on a 6 MP photo, but
  // it loses the finest scales and with them repeatability under scale change (measured
  // on fountain_p11, docs/measurement_history.md "Front end speed": 0.84 -> 0.70 of the keypoints repeated
  // under a 0.8x zoom and 15 degree rotation): an option, not the default.
  int first_octave = -1;
  // Adaptive contrast (weakly textured or low-contrast images): when an image yields fewer
  // than target_features keypoints, detection runs again with the contrast threshold halved,
  // until the target is reached or the threshold would fall below min_contrast_threshold.
  // 0 = off (the default: a textured photo reaches max_features at the fixed threshold).
  // FeatureSet::contrast_threshold records where each image ended.
  int target_features = 0;
  double min_contrast_threshold = 0.0025;

  // Empty when valid, else one line naming the first field out of its range (the table of
  // io/option_ranges.cc under "features.sift") or breaking a rule between fields.
  std::string Check() const;
};
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(SiftOptions, implementation, max_features, root_sift, max_image_size,
                                                contrast_threshold, edge_threshold, first_octave, target_features,
                                                min_contrast_threshold)

// Full-resolution pixels per detection pixel for an image of this size (1 if not downscaled
// by max_image_size; the first-octave mode does not change it).
double DetectionScale(int width, int height, const SiftOptions& options);

// The options with implementation "auto" resolved for an image of this size ("pgba" or
// "opencv"; the others as they are): what ExtractSift runs on it and what its cache key says.
SiftOptions SiftOptionsForImage(const SiftOptions& options, int width, int height);

// Features of an 8-bit grayscale image (CV_8UC1). Deterministic (no randomness in SIFT).
// Keypoints are sorted by decreasing response, ties by position, so the cache and the matcher
// see the same order on every run.
FeatureSet ExtractSift(const cv::Mat& gray, const SiftOptions& options);

// A short string that changes whenever an option affecting the features changes; stored in
// the feature cache so a re-run with other options recomputes instead of reusing.
std::string SiftOptionsKey(const SiftOptions& options);

}  // namespace pgba
