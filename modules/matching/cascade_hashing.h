// Cascade hashing (Cheng, Leng, Wu and Lu, "Fast and accurate image matching with cascade
// hashing for 3D reconstruction", CVPR 2014), the approximate nearest-neighbour search of
// the matcher: every descriptor gets a 128-bit code (signs of random projections of the
// descriptor minus the run's mean descriptor) and a few short bucket codes; a query's
// candidates are the descriptors sharing at least one bucket with it, ranked by the Hamming
// distance of the long codes, and only the best-ranked few are compared by the exact L2
// distance of the uint8 descriptors. Integer arithmetic and fixed tie-breaking: the result
// is a function of the inputs alone.
#pragma once

#include <string>

#include <cstdint>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <vector>

namespace pgba {

struct CascadeHashingOptions {
  // Bucket tables (a candidate shares its bucket in at least one) and the longest bucket
  // code (2^bits buckets per table).
  int num_tables = 6;
  int bits_per_bucket = 8;
  // An image's bucket codes are shortened until its buckets hold about this many
  // descriptors (8 bits at 8192 features, 2 bits at 230): a query meets as many candidates
  // on a weakly textured image as on a rich one instead of an almost empty bucket.
  int target_bucket_size = 32;
  // Candidates with the fewest differing code bits whose L2 distance is computed.
  int num_reranked = 10;
  // Empty when valid, else one line naming the first field out of its valid range (the
  // ranges of io/option_ranges.cc) or breaking a rule between fields.
  std::string Check() const;
};
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(CascadeHashingOptions, num_tables, bits_per_bucket,
                                                target_bucket_size, num_reranked)

// Throws InputError naming the option when one is out of its valid range.
void ValidateCascadeHashingOptions(const CascadeHashingOptions& options);

// The projections shared by every image of one matching run (codes of two images are only
// comparable if made by the same hasher).
class CascadeHasher {
 public:
  // mean_descriptor: 1 x 128 CV_32F, the mean of the run's descriptors (sign codes need
  // centred inputs). The projections are drawn from `seed`.
  CascadeHasher(const cv::Mat& mean_descriptor, const CascadeHashingOptions& options, uint64_t seed);

  const CascadeHashingOptions& options() const { return options_; }
  const cv::Mat& mean() const { return mean_; }
  const cv::Mat& projections() const { return projections_; }  // (128 + tables*bits) x 128

 private:
  CascadeHashingOptions options_;
  cv::Mat mean_;
  cv::Mat projections_;
};

// The uint8 descriptors of one image with their codes and bucket lists.
class HashedDescriptors {
 public:
  HashedDescriptors(const cv::Mat& descriptors_u8, const CascadeHasher& hasher);
  HashedDescriptors(const HashedDescriptors&) = delete;
  HashedDescriptors& operator=(const HashedDescriptors&) = delete;

  int size() const { return descriptors_.rows; }
  const cv::Mat& descriptors() const { return descriptors_; }

  // For the given rows of `queries` (all rows if `rows` is null): index and L2 distance of
  // the nearest descriptor found here, and the distance of the second nearest (infinity
  // where fewer than one / two candidates were found; index -1 where none).
  void SearchBestTwo(const HashedDescriptors& queries, const std::vector<int>* rows, std::vector<int>* best,
                     std::vector<float>* best_dist, std::vector<float>* second_dist) const;

 private:
  cv::Mat descriptors_;                 // CV_8U, n x 128 (shares the caller's data)
  std::vector<uint64_t> codes_;         // 2 words per descriptor
  std::vector<uint16_t> bucket_of_;     // num_tables full-length codes per descriptor
  std::vector<int> bucket_start_;       // per table, 2^bits + 1 offsets into bucket_members_
  std::vector<int> bucket_members_;     // per table, descriptor indices grouped by bucket
  // The long codes of bucket_members_, in its order (2 words per entry): a query reads its
  // buckets' codes sequentially instead of one random cache line of codes_ per candidate
  // (perf, fountain_p11: the loads of codes_ and of the per-query `seen` marks held about
  // half of the search's samples). 0.75 MiB more per image at 8192 features and 6 tables.
  std::vector<uint64_t> bucket_codes_;
  int num_tables_ = 0;
  int num_buckets_ = 0;  // of this image: 2^(bits used here)
  int num_reranked_ = 0;
};

// Mean of the rows of several uint8 descriptor matrices (1 x 128 CV_32F), summed exactly.
cv::Mat MeanDescriptor(const std::vector<cv::Mat>& descriptors_u8);

}  // namespace pgba
