// The features of one image: SIFT keypoints and their descriptors, as the matching stage
// consumes them.
//
// Coordinates follow COLMAP's convention (the centre of the upper-left pixel is (0.5, 0.5)),
// because calibrations arrive as COLMAP cameras.txt, and are in full-resolution pixels even
// when the detector ran on a downscaled copy of the image.
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

namespace pgba {

struct Keypoint {
  float x = 0.f;  // pixels, full resolution, COLMAP convention
  float y = 0.f;
  float scale = 0.f;        // detector scale (OpenCV KeyPoint::size / 2), full-resolution pixels
  float orientation = 0.f;  // radians
};

struct FeatureSet {
  int width = 0;  // full-resolution image size
  int height = 0;
  // The SIFT contrast threshold the detection ended at: SiftOptions::contrast_threshold, or
  // lower where the adaptive detection (SiftOptions::target_features) lowered it.
  float contrast_threshold = 0.f;
  std::vector<Keypoint> keypoints;
  // One row of kSiftDescriptorSize uint8 per keypoint (CV_8U); SIFT or RootSIFT quantised
  // as in COLMAP (round(512 * v), saturated at 255).
  cv::Mat descriptors;

  size_t size() const { return keypoints.size(); }
};

constexpr int kSiftDescriptorSize = 128;

}  // namespace pgba
