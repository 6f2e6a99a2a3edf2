#include "matching/descriptor_matcher.h"

#include <cmath>
#include <limits>

namespace pgba {

DescriptorIndex::DescriptorIndex(const cv::Mat& descriptors_u8, const DescriptorMatchOptions& options, uint64_t seed)
    : checks_(options.checks) {
  descriptors_u8.convertTo(data_, CV_32F);
  if (data_.rows < 2) return;  // nothing to match against (ratio test needs two)
  // cvflann draws its random split dimensions from cv::theRNG(), which is per thread:
  // seeding it here makes the forest a function of (descriptors, seed) whichever TBB
  // thread builds it.
  cv::theRNG() = cv::RNG(seed * 2654435761ULL + 1);
  index_ = std::make_unique<cv::flann::Index>(data_, cv::flann::KDTreeIndexParams(options.kdtree_trees),
                                              cvflann::FLANN_DIST_L2);
}

void DescriptorIndex::SearchBestTwo(const cv::Mat& queries, std::vector<int>* best, std::vector<float>* best_dist,
                                    std::vector<float>* second_dist) const {
  const int n = queries.rows;
  best->assign(n, -1);
  best_dist->assign(n, std::numeric_limits<float>::infinity());
  second_dist->assign(n, std::numeric_limits<float>::infinity());
  if (!index_ || n == 0) return;
  cv::Mat indices(n, 2, CV_32S), dists(n, 2, CV_32F);
  index_->knnSearch(queries, indices, dists, 2, cv::flann::SearchParams(checks_));
  for (int i = 0; i < n; ++i) {
    // FLANN returns squared L2 distances.
    (*best)[i] = indices.at<int>(i, 0);
    (*best_dist)[i] = std::sqrt(std::max(0.f, dists.at<float>(i, 0)));
    (*second_dist)[i] = std::sqrt(std::max(0.f, dists.at<float>(i, 1)));
  }
}

namespace {

// Best neighbour per query that passes the ratio test and the distance bound, else -1.
std::vector<int> FilteredBest(const DescriptorIndex& queries, const DescriptorIndex& target,
                              const DescriptorMatchOptions& options) {
  std::vector<int> best;
  std::vector<float> d1, d2;
  target.SearchBestTwo(queries.data(), &best, &d1, &d2);
  const float max_dist = static_cast<float>(options.max_distance * 512.0);
  for (size_t i = 0; i < best.size(); ++i)
    if (best[i] < 0 || d1[i] > max_dist || !(d1[i] < options.max_ratio * d2[i])) best[i] = -1;
  return best;
}

}  // namespace

std::vector<std::pair<uint32_t, uint32_t>> MatchDescriptors(const DescriptorIndex& image1,
                                                            const DescriptorIndex& image2,
                                                            const DescriptorMatchOptions& options) {
  std::vector<std::pair<uint32_t, uint32_t>> matches;
  if (image1.size() < 2 || image2.size() < 2) return matches;
  const std::vector<int> forward = FilteredBest(image1, image2, options);
  std::vector<int> backward;
  if (options.cross_check) backward = FilteredBest(image2, image1, options);
  for (size_t i = 0; i < forward.size(); ++i) {
    const int j = forward[i];
    if (j < 0) continue;
    if (options.cross_check && backward[j] != static_cast<int>(i)) continue;
    matches.emplace_back(static_cast<uint32_t>(i), static_cast<uint32_t>(j));
  }
  return matches;
}

}  // namespace pgba
