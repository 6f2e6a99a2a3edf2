// Guided matching along a verified epipolar geometry: the features of image 1 are matched
// only against the features of image 2 near their epipolar line, where the descriptor test
// competes with a few candidates instead of the whole image. On weakly textured images the
// ratio test over the whole image rejects most true matches (the second best is almost as
// good somewhere else in the image); within the epipolar band most of those competitors are
// gone. Run on the weak pairs only: the band test costs n1 x n2 Sampson evaluations.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <string>
#include <utility>
#include <vector>

#include "features/feature_set.h"
#include "pgba/scene/camera.h"

namespace pgba {

struct GuidedMatchingOptions {
  // Off by default and in the object_ring preset: the textured sets have matches enough,
  // and on dino_sparse_ring its extra matches put pair rotations 1-5 deg off (docs/measurement_history.md,
  // "Weakly textured objects").
  bool enabled = false;
  // Only pairs whose first verification found fewer inliers than this (a dense pair gains
  // little and costs the most) and at least `min_inliers` (below that the geometry that
  // would guide the search is itself a guess).
  int max_inliers = 300;
  int min_inliers = 15;
  // Half width of the epipolar band (Sampson distance), pixels of the images SIFT ran on.
  double threshold_px = 2.0;
  // Ratio test among the candidates in the band (best < max_ratio * second best) and the
  // absolute bound on the best distance (x 512, as DescriptorMatchOptions::max_distance).
  double max_ratio = 0.9;
  double max_distance = 0.7;
  // With triplets, transfer into the third view (third_view_transfer.h): after verification
  // (and the weak pairs' confirmation), every triangle of kept pairs whose baselines close
  // gives its pairs' matches a partner in the third view where one lies within threshold_px
  // of the transferred point and passes the descriptor tests above. Independent of
  // `enabled` (the pairwise guided matching).
  bool transfer = false;

  // "" if valid, else "key: problem" (the key relative to the section).
  std::string Check() const;
};
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(GuidedMatchingOptions, enabled, max_inliers, min_inliers,
                                                threshold_px, max_ratio, max_distance, transfer)

// L2 distance of two SIFT descriptors (kSiftDescriptorSize bytes each).
float SiftDistance(const uint8_t* a, const uint8_t* b);

// The nearest and second nearest descriptor among the candidates offered.
struct NearestTwo {
  int index = -1;
  float best = std::numeric_limits<float>::infinity();
  float second = std::numeric_limits<float>::infinity();
  void Offer(int k, float d);
  // A nearest within options.max_distance (x 512) and below max_ratio x the second.
  bool Passes(const GuidedMatchingOptions& options) const;
};

// Mutual best matches (i in image 1, j in image 2) among the pairs within the epipolar band
// of x_2 = R_21 x_1 + t_21 and in front of both cameras, sorted by i. `focal_px` converts
// the threshold to an angle.
std::vector<std::pair<uint32_t, uint32_t>> GuidedMatches(const Eigen::Matrix3d& R_21, const Eigen::Vector3d& t_21,
                                                         const std::vector<Eigen::Vector3d>& bearings1,
                                                         const cv::Mat& descriptors1,
                                                         const std::vector<Eigen::Vector3d>& bearings2,
                                                         const cv::Mat& descriptors2, double focal_px,
                                                         double threshold_px, const GuidedMatchingOptions& options);

}  // namespace pgba
