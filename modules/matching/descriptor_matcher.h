// Putative matches between the SIFT descriptors of two images: approximate nearest
// neighbours with a FLANN randomised kd-forest (cv::flann), Lowe's ratio test, an absolute
// distance bound and a mutual (cross) check.
#pragma once

#include <cstdint>
#include <memory>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/flann.hpp>
#include <utility>
#include <vector>

namespace pgba {

struct DescriptorMatchOptions {
  // Lowe's ratio: best distance < max_ratio * second best (COLMAP's default).
  double max_ratio = 0.8;
  // Best distance < max_distance * 512 (descriptors are quantised on a 512 scale: unit
  // vectors for RootSIFT); COLMAP's default.
  double max_distance = 0.7;
  // Keep i->j only if j's best match in image 1 is i.
  bool cross_check = true;
  // FLANN kd-forest: number of randomised trees and of leaves checked per query (more
  // checks = closer to exact search, slower). On temple_sparse_ring 128 checks cost 4x the
  // time of 32 for the same number of putative matches (4709 vs 4787) and verified pairs.
  int kdtree_trees = 4;
  int checks = 32;
};
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(DescriptorMatchOptions, max_ratio, max_distance, cross_check,
                                                kdtree_trees, checks)

// The descriptors of one image with their kd-forest. Building is deterministic for a given
// seed (the forest's randomness comes from OpenCV's thread-local RNG, seeded here);
// searching is const and may run from several threads at once.
class DescriptorIndex {
 public:
  DescriptorIndex(const cv::Mat& descriptors_u8, const DescriptorMatchOptions& options, uint64_t seed);
  DescriptorIndex(const DescriptorIndex&) = delete;
  DescriptorIndex& operator=(const DescriptorIndex&) = delete;

  int size() const { return data_.rows; }
  const cv::Mat& data() const { return data_; }  // CV_32F

  // For every row of `queries` (CV_32F): index and L2 distance of its best match, and the
  // distance of the second best (infinity when the index holds a single descriptor).
  void SearchBestTwo(const cv::Mat& queries, std::vector<int>* best, std::vector<float>* best_dist,
                     std::vector<float>* second_dist) const;

 private:
  cv::Mat data_;
  int checks_;
  // cv::flann's search is logically const; its pooled per-thread heaps make it thread-safe.
  mutable std::unique_ptr<cv::flann::Index> index_;
};

// Matches image 1 -> image 2 as (feature index in 1, feature index in 2), sorted by the
// index in image 1.
std::vector<std::pair<uint32_t, uint32_t>> MatchDescriptors(const DescriptorIndex& image1,
                                                            const DescriptorIndex& image2,
                                                            const DescriptorMatchOptions& options);

}  // namespace pgba
