#include "matching/descriptor_matcher.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "pgba/io/option_ranges.h"
#include "pgba/util/error.h"

namespace pgba {

void ValidateDescriptorMatchOptions(const DescriptorMatchOptions& o) {
  if (o.method != "cascade_hashing" && o.method != "kdtree")
    throw InputError("matching.descriptors.method = \"" + o.method + "\": must be cascade_hashing or kdtree");
  if (o.method == "cascade_hashing") ValidateCascadeHashingOptions(o.cascade_hashing);
}

DescriptorIndex::DescriptorIndex(const cv::Mat& descriptors_u8, const DescriptorMatchOptions& options, uint64_t seed,
                                 const CascadeHasher* hasher)
    : descriptors_u8_(descriptors_u8), checks_(options.checks) {
  ValidateDescriptorMatchOptions(options);
  if (descriptors_u8.rows < 2) return;  // nothing to match against (ratio test needs two)
  if (options.method == "cascade_hashing") {
    CV_Assert(hasher != nullptr);
    hashed_ = std::make_unique<HashedDescriptors>(descriptors_u8, *hasher);
    return;
  }
  descriptors_u8.convertTo(data_, CV_32F);
  // cvflann draws its random split dimensions from cv::theRNG(), which is per thread:
  // seeding it here makes the forest a function of (descriptors, seed) whichever TBB
  // thread builds it.
  cv::theRNG() = cv::RNG(seed * 2654435761ULL + 1);
  index_ = std::make_unique<cv::flann::Index>(data_, cv::flann::KDTreeIndexParams(options.kdtree_trees),
                                              cvflann::FLANN_DIST_L2);
}

void DescriptorIndex::SearchBestTwo(const DescriptorIndex& queries, const std::vector<int>* rows,
                                    std::vector<int>* best, std::vector<float>* best_dist,
                                    std::vector<float>* second_dist) const {
  const int n = rows ? static_cast<int>(rows->size()) : queries.size();
  if (hashed_ && queries.hashed_) {
    hashed_->SearchBestTwo(*queries.hashed_, rows, best, best_dist, second_dist);
    return;
  }
  best->assign(n, -1);
  best_dist->assign(n, std::numeric_limits<float>::infinity());
  second_dist->assign(n, std::numeric_limits<float>::infinity());
  if (!index_ || n == 0 || queries.size() == 0) return;
  cv::Mat query_data;
  queries.descriptors_u8_.convertTo(query_data, CV_32F);
  if (rows) {
    cv::Mat selected(n, query_data.cols, CV_32F);
    for (int k = 0; k < n; ++k) query_data.row((*rows)[k]).copyTo(selected.row(k));
    query_data = selected;
  }
  cv::Mat indices(n, 2, CV_32S), dists(n, 2, CV_32F);
  index_->knnSearch(query_data, indices, dists, 2, cv::flann::SearchParams(checks_));
  for (int i = 0; i < n; ++i) {
    // FLANN returns squared L2 distances.
    (*best)[i] = indices.at<int>(i, 0);
    (*best_dist)[i] = std::sqrt(std::max(0.f, dists.at<float>(i, 0)));
    (*second_dist)[i] = std::sqrt(std::max(0.f, dists.at<float>(i, 1)));
  }
}

namespace {

// Marks the best neighbours that fail the ratio test or the distance bound as -1.
void FilterBest(const std::vector<float>& d1, const std::vector<float>& d2, const DescriptorMatchOptions& options,
                std::vector<int>* best) {
  const float max_dist = static_cast<float>(options.max_distance * 512.0);
  for (size_t i = 0; i < best->size(); ++i)
    if ((*best)[i] < 0 || d1[i] > max_dist || !(d1[i] < options.max_ratio * d2[i])) (*best)[i] = -1;
}

}  // namespace

std::vector<std::pair<uint32_t, uint32_t>> MatchDescriptors(const DescriptorIndex& image1,
                                                            const DescriptorIndex& image2,
                                                            const DescriptorMatchOptions& options) {
  std::vector<std::pair<uint32_t, uint32_t>> matches;
  if (image1.size() < 2 || image2.size() < 2) return matches;
  std::vector<int> forward;
  std::vector<float> d1, d2;
  image2.SearchBestTwo(image1, nullptr, &forward, &d1, &d2);
  FilterBest(d1, d2, options, &forward);
  // The mutual check only needs the backward best match of the features of image 2 that
  // some forward match points to: searching those alone returns the same matches for a
  // fraction of the second search (the search of one query does not depend on the others).
  std::vector<int> backward_of;  // feature of image 2 -> its filtered best match in image 1
  if (options.cross_check) {
    std::vector<int> targets;
    for (int j : forward)
      if (j >= 0) targets.push_back(j);
    std::sort(targets.begin(), targets.end());
    targets.erase(std::unique(targets.begin(), targets.end()), targets.end());
    std::vector<int> backward;
    image1.SearchBestTwo(image2, &targets, &backward, &d1, &d2);
    FilterBest(d1, d2, options, &backward);
    backward_of.assign(image2.size(), -1);
    for (size_t k = 0; k < targets.size(); ++k) backward_of[targets[k]] = backward[k];
  }
  for (size_t i = 0; i < forward.size(); ++i) {
    const int j = forward[i];
    if (j < 0) continue;
    if (options.cross_check && backward_of[j] != static_cast<int>(i)) continue;
    matches.emplace_back(static_cast<uint32_t>(i), static_cast<uint32_t>(j));
  }
  return matches;
}

std::string DescriptorMatchOptions::Check() const {
  if (const std::string m = CheckRanges(*this, "matching.descriptors"); !m.empty()) return m;
  return "";
}

}  // namespace pgba
