// The features stage: image folder + calibration -> SIFT features of every usable image in
// the workspace (feature_index.h), in parallel over images, skipping images whose cached
// features were computed from the same file with the same options.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "features/feature_index.h"
#include "features/image_catalog.h"
#include "features/sift_extractor.h"

namespace pgba {

struct FeatureExtractionOptions {
  SiftOptions sift;
  // Reuse WS/features/<name>.bin when its key (options + source size and mtime) matches.
  bool use_cache = true;
  // Images processed at once (0 = one per core). Each needs one SIFT scale space in memory,
  // ~400 MB at 1600 px and ~1.5 GB at 3200 px: lower this on many-core, small-memory hosts.
  int max_parallel_images = 0;
  // Keep the large OpenCV buffers of a finished image for the next one (buffer_pool.h)
  // instead of returning them to the system; false only to measure what that saves.
  bool reuse_buffers = true;

  // Empty when valid, else one line naming the first invalid field ("sift.max_features = 0 is
  // out of range (>= 1)"; the table of io/option_ranges.cc under "features").
  std::string Check() const;
};
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(FeatureExtractionOptions, sift, use_cache, max_parallel_images,
                                                reuse_buffers)

struct SkippedImage {
  std::string name;
  std::string reason;
};

struct FeatureExtractionResult {
  FeatureIndex index;                 // the accepted images (ids 1..n in name order)
  std::vector<SkippedImage> skipped;  // each also logged as a warning naming the file
  // Images whose contrast threshold the adaptive detection lowered (SiftOptions::
  // target_features), with the threshold they ended at, in name order.
  std::vector<std::pair<std::string, float>> adapted_contrast;
  int num_extracted = 0;              // images processed in this run
  int num_cached = 0;                 // images whose cached features were reused
  double megapixels_extracted = 0.0;  // full-resolution megapixels of the extracted images
  std::string calibration_source;     // ImageCatalog::calibration_source
  double seconds = 0.0;               // wall time of the stage
};

// Files that are not decodable images, images with a size other than their camera's, and
// images without a camera are skipped with a warning; if no image is left the run stops with
// an InputError. Results do not depend on the number of threads.
FeatureExtractionResult ExtractFeatures(const std::string& images_dir, const CalibrationInput& calibration,
                                        const std::string& workspace, const FeatureExtractionOptions& options);

// The stage's record in report.json (`pgba features` and `pgba run`): image counts, skipped
// images with reasons, megapixels, seconds per megapixel, mean features per image, and the
// images whose contrast threshold was lowered (adapted_contrast_threshold: name -> threshold).
nlohmann::json FeatureExtractionRecord(const FeatureExtractionResult& result);

}  // namespace pgba
