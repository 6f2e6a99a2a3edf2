// Putative matches between the SIFT descriptors of two images: approximate nearest
// neighbours by cascade hashing (cascade_hashing.h, the default) or a FLANN randomised
// kd-forest (cv::flann), Lowe's ratio test, an absolute distance bound and a mutual (cross)
// check.
#pragma once

#include <cstdint>
#include <memory>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/flann.hpp>
#include <string>
#include <utility>
#include <vector>

#include "matching/cascade_hashing.h"

namespace pgba {

struct DescriptorMatchOptions {
  // Lowe's ratio: best distance < max_ratio * second best (COLMAP's default).
  double max_ratio = 0.8;
  // Best distance < max_distance * 512 (descriptors are quantised on a 512 scale: unit
  // vectors for RootSIFT); COLMAP's default.
  double max_distance = 0.7;
  // Keep i->j only if j's best match in image 1 is i.
  bool cross_check = true;
  // "cascade_hashing" or "kdtree". Measured on fountain_p11 (8192 features per image, 2
  // cores): see the README's front-end table; cascade hashing finds as many mutual matches
  // as the kd-forest at 32 checks for a fraction of its time.
  std::string method = "cascade_hashing";
  CascadeHashingOptions cascade_hashing;
  // FLANN kd-forest: number of randomised trees and of leaves checked per query (more
  // checks = closer to exact search, slower). On temple_sparse_ring 128 checks cost 4x the
  // time of 32 for the same number of putative matches (4709 vs 4787) and verified pairs.
  int kdtree_trees = 4;
  int checks = 32;
  // Empty when valid, else one line naming the first field out of its valid range (the
  // ranges of io/option_ranges.cc) or breaking a rule between fields.
  std::string Check() const;
};
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(DescriptorMatchOptions, max_ratio, max_distance, cross_check, method,
                                                cascade_hashing, kdtree_trees, checks)

// Throws InputError naming the option when one is out of its valid range.
void ValidateDescriptorMatchOptions(const DescriptorMatchOptions& options);

// The descriptors of one image with their search structure. Building is deterministic for a
// given seed (the kd-forest's randomness comes from OpenCV's thread-local RNG, seeded here;
// cascade hashing uses the run's shared hasher); searching is const and may run from
// several threads at once.
class DescriptorIndex {
 public:
  // `hasher` is required for cascade hashing (and must outlive the index), unused otherwise.
  DescriptorIndex(const cv::Mat& descriptors_u8, const DescriptorMatchOptions& options, uint64_t seed,
                  const CascadeHasher* hasher = nullptr);
  DescriptorIndex(const DescriptorIndex&) = delete;
  DescriptorIndex& operator=(const DescriptorIndex&) = delete;

  int size() const { return descriptors_u8_.rows; }

  // For the rows `rows` of `queries` (all rows if null): index and L2 distance of the best
  // match here, and the distance of the second best (infinity when not found).
  void SearchBestTwo(const DescriptorIndex& queries, const std::vector<int>* rows, std::vector<int>* best,
                     std::vector<float>* best_dist, std::vector<float>* second_dist) const;

 private:
  cv::Mat descriptors_u8_;
  cv::Mat data_;  // CV_32F copy for the kd-forest
  int checks_;
  // cv::flann's search is logically const; its pooled per-thread heaps make it thread-safe.
  mutable std::unique_ptr<cv::flann::Index> index_;
  std::unique_ptr<HashedDescriptors> hashed_;
};

// Matches image 1 -> image 2 as (feature index in 1, feature index in 2), sorted by the
// index in image 1.
std::vector<std::pair<uint32_t, uint32_t>> MatchDescriptors(const DescriptorIndex& image1,
                                                            const DescriptorIndex& image2,
                                                            const DescriptorMatchOptions& options);

}  // namespace pgba
