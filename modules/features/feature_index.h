// What the features stage leaves in the workspace for the matching stage:
//   WS/features/cameras.txt   the calibration (COLMAP cameras.txt)
//   WS/features/images.json   the accepted images: id, name, camera, size, feature count
//   WS/features/<name>.bin    the features of each image (feature_file.h)
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "pgba/scene/camera.h"

namespace pgba {

struct IndexedImage {
  uint32_t image_id = 0;
  std::string name;
  uint32_t camera_id = 0;
  int width = 0;
  int height = 0;
  int num_features = 0;
  // Full-resolution pixels per pixel of the image SIFT ran on (>= 1 when downscaled):
  // keypoint noise grows with it, so verification thresholds scale with it.
  double detection_scale = 1.0;
};

struct FeatureIndex {
  std::map<uint32_t, Camera> cameras;
  std::vector<IndexedImage> images;  // sorted by image id
};

std::string FeaturesDir(const std::string& workspace);
std::string FeatureFilePath(const std::string& workspace, const std::string& image_name);

// Writes cameras.txt and images.json atomically.
void WriteFeatureIndex(const std::string& workspace, const FeatureIndex& index);
// InputError if the workspace has no (valid) index: "run pgba features first".
FeatureIndex ReadFeatureIndex(const std::string& workspace);

}  // namespace pgba
