#include "matching/cascade_hashing.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "pgba/io/option_ranges.h"
#include "features/feature_set.h"
#include "pgba/util/error.h"

namespace pgba {
namespace {

constexpr int kCodeBits = 128;  // long code: two 64-bit words
// Fixed-point scales: centred descriptors x - mean in 1/8 units and projections in 1/256
// units fit int16 and their 128-term dot products int32, so codes are exact integers.
constexpr double kDescriptorScale = 8.0;
constexpr double kProjectionScale = 256.0;

// Hot loops are compiled twice, for AVX2 machines and for any x86-64, and the loader picks
// (GCC function multi-versioning); the integer results are the same either way.
#if defined(__GNUC__) && defined(__x86_64__) && !defined(__clang__)
#define PGBA_SIMD_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define PGBA_SIMD_CLONES
#endif

inline int SquaredL2(const uint8_t* a, const uint8_t* b) {
  int s = 0;
  for (int k = 0; k < kSiftDescriptorSize; ++k) {
    const int d = int(a[k]) - int(b[k]);
    s += d * d;
  }
  return s;
}

// Signs of every projection of every centred descriptor: bit k of row i is set when
// projection k of descriptor i is positive.
PGBA_SIMD_CLONES
void ProjectionSigns(const cv::Mat& descriptors, const std::vector<int16_t>& mean, const std::vector<int16_t>& proj,
                     int num_proj, std::vector<uint8_t>* signs) {
  signs->assign(static_cast<size_t>(descriptors.rows) * num_proj, 0);
  int16_t centred[kSiftDescriptorSize];
  for (int i = 0; i < descriptors.rows; ++i) {
    const uint8_t* d = descriptors.ptr<uint8_t>(i);
    for (int k = 0; k < kSiftDescriptorSize; ++k)
      centred[k] = static_cast<int16_t>(int(d[k]) * int(kDescriptorScale) - mean[k]);
    for (int p = 0; p < num_proj; ++p) {
      const int16_t* w = &proj[static_cast<size_t>(p) * kSiftDescriptorSize];
      int dot = 0;
      for (int k = 0; k < kSiftDescriptorSize; ++k) dot += int(centred[k]) * int(w[k]);
      (*signs)[static_cast<size_t>(i) * num_proj + p] = dot > 0;
    }
  }
}

// Moves the `k` smallest keys (Hamming distance << 32 | index) of `candidates` to its front
// and returns how many there are (k, or fewer candidates): the same set std::nth_element
// selects, but by `hist`, the histogram of their distances (0-128, counted as they were
// collected), since a general selection over the ~200 candidates of each query was a third
// of all matching time (perf, fountain_p11). Keys at the cut-off distance are taken by
// increasing index, as the key order does.
size_t SelectSmallest(size_t k, const uint16_t* hist, uint64_t* c, size_t size, std::vector<uint64_t>* ties) {
  if (size <= k) return size;
  size_t below = 0;  // keys with a distance under the cut-off
  uint64_t cut = 0;
  while (below + hist[cut] < k) below += hist[cut++];
  // Both lists compacted without branches (whether a key is kept is data-dependent, a
  // branch on it mispredicted often enough to make this loop a tenth of the search).
  ties->resize(size);
  uint64_t* t = ties->data();
  size_t n = 0, num_ties = 0;
  for (size_t m = 0; m < size; ++m) {
    const uint64_t key = c[m];
    const uint64_t d = key >> 32;
    c[n] = key;
    n += d < cut;
    t[num_ties] = key;
    num_ties += d == cut;
  }
  const size_t from_ties = k - below;
  if (num_ties > from_ties) std::nth_element(t, t + from_ties, t + num_ties);
  std::copy(t, t + from_ties, c + n);
  return k;
}

}  // namespace

void ValidateCascadeHashingOptions(const CascadeHashingOptions& o) {
  auto check = [](bool ok, const std::string& name, const std::string& range, double value) {
    if (!ok) throw InputError("matching.descriptors.cascade_hashing." + name + " = " + std::to_string(value) +
                              ": must be " + range);
  };
  check(o.num_tables >= 1 && o.num_tables <= 32, "num_tables", "in [1, 32]", o.num_tables);
  check(o.bits_per_bucket >= 1 && o.bits_per_bucket <= 16, "bits_per_bucket", "in [1, 16]", o.bits_per_bucket);
  check(o.target_bucket_size >= 1, "target_bucket_size", ">= 1", o.target_bucket_size);
  check(o.num_reranked >= 2 && o.num_reranked <= 1000, "num_reranked", "in [2, 1000]", o.num_reranked);
}

CascadeHasher::CascadeHasher(const cv::Mat& mean_descriptor, const CascadeHashingOptions& options, uint64_t seed)
    : options_(options), mean_(mean_descriptor.clone()) {
  ValidateCascadeHashingOptions(options);
  CV_Assert(mean_.type() == CV_32F && mean_.rows == 1 && mean_.cols == kSiftDescriptorSize);
  projections_.create(kCodeBits + options.num_tables * options.bits_per_bucket, kSiftDescriptorSize, CV_32F);
  cv::RNG rng(seed);
  rng.fill(projections_, cv::RNG::NORMAL, 0.0, 1.0);
}

cv::Mat MeanDescriptor(const std::vector<cv::Mat>& descriptors_u8) {
  std::vector<int64_t> sum(kSiftDescriptorSize, 0);
  int64_t n = 0;
  for (const cv::Mat& d : descriptors_u8) {
    for (int i = 0; i < d.rows; ++i)
      for (int k = 0; k < kSiftDescriptorSize; ++k) sum[k] += d.at<uint8_t>(i, k);
    n += d.rows;
  }
  cv::Mat mean(1, kSiftDescriptorSize, CV_32F, cv::Scalar(0));
  for (int k = 0; k < kSiftDescriptorSize; ++k)
    if (n > 0) mean.at<float>(0, k) = static_cast<float>(static_cast<double>(sum[k]) / n);
  return mean;
}

HashedDescriptors::HashedDescriptors(const cv::Mat& descriptors_u8, const CascadeHasher& hasher)
    : descriptors_(descriptors_u8) {
  CV_Assert(descriptors_.type() == CV_8U && (descriptors_.empty() || descriptors_.cols == kSiftDescriptorSize));
  const CascadeHashingOptions& o = hasher.options();
  num_tables_ = o.num_tables;
  num_reranked_ = o.num_reranked;
  const int n = descriptors_.rows;
  int bits = 0;
  while (bits < o.bits_per_bucket && (static_cast<int64_t>(o.target_bucket_size) << (bits + 1)) <= n) ++bits;
  num_buckets_ = 1 << bits;
  const int num_proj = hasher.projections().rows;

  std::vector<int16_t> mean(kSiftDescriptorSize), proj(static_cast<size_t>(num_proj) * kSiftDescriptorSize);
  for (int k = 0; k < kSiftDescriptorSize; ++k)
    mean[k] = static_cast<int16_t>(std::lround(hasher.mean().at<float>(0, k) * kDescriptorScale));
  for (int p = 0; p < num_proj; ++p)
    for (int k = 0; k < kSiftDescriptorSize; ++k)
      proj[static_cast<size_t>(p) * kSiftDescriptorSize + k] = static_cast<int16_t>(
          std::clamp(std::lround(hasher.projections().at<float>(p, k) * kProjectionScale), -32767L, 32767L));
  std::vector<uint8_t> signs;
  ProjectionSigns(descriptors_, mean, proj, num_proj, &signs);

  codes_.assign(2 * static_cast<size_t>(n), 0);
  bucket_of_.assign(static_cast<size_t>(n) * num_tables_, 0);
  for (int i = 0; i < n; ++i) {
    const uint8_t* s = &signs[static_cast<size_t>(i) * num_proj];
    for (int k = 0; k < kCodeBits; ++k)
      if (s[k]) codes_[2 * i + k / 64] |= uint64_t(1) << (k % 64);
    for (int t = 0; t < num_tables_; ++t) {
      int key = 0;
      for (int b = 0; b < o.bits_per_bucket; ++b)
        if (s[kCodeBits + t * o.bits_per_bucket + b]) key |= 1 << b;
      bucket_of_[static_cast<size_t>(i) * num_tables_ + t] = static_cast<uint16_t>(key);
    }
  }
  // Bucket lists in CSR form, members in increasing index order, each with its long code.
  bucket_start_.assign(static_cast<size_t>(num_tables_) * (num_buckets_ + 1), 0);
  bucket_members_.assign(static_cast<size_t>(num_tables_) * n, 0);
  bucket_codes_.assign(2 * static_cast<size_t>(num_tables_) * n, 0);
  for (int t = 0; t < num_tables_; ++t) {
    int* start = &bucket_start_[static_cast<size_t>(t) * (num_buckets_ + 1)];
    const int mask = num_buckets_ - 1;
    for (int i = 0; i < n; ++i) ++start[(bucket_of_[static_cast<size_t>(i) * num_tables_ + t] & mask) + 1];
    for (int b = 0; b < num_buckets_; ++b) start[b + 1] += start[b];
    std::vector<int> fill(start, start + num_buckets_);
    int* members = &bucket_members_[static_cast<size_t>(t) * n];
    for (int i = 0; i < n; ++i) members[fill[bucket_of_[static_cast<size_t>(i) * num_tables_ + t] & mask]++] = i;
    uint64_t* member_codes = &bucket_codes_[2 * static_cast<size_t>(t) * n];
    for (int m = 0; m < n; ++m) {
      member_codes[2 * m] = codes_[2 * static_cast<size_t>(members[m])];
      member_codes[2 * m + 1] = codes_[2 * static_cast<size_t>(members[m]) + 1];
    }
  }
}

PGBA_SIMD_CLONES
void HashedDescriptors::SearchBestTwo(const HashedDescriptors& queries, const std::vector<int>* rows,
                                      std::vector<int>* best, std::vector<float>* best_dist,
                                      std::vector<float>* second_dist) const {
  CV_Assert(queries.num_tables_ == num_tables_);
  const int mask = num_buckets_ - 1;  // the query's code cut to this image's length
  const int num_queries = rows ? static_cast<int>(rows->size()) : queries.size();
  constexpr float kInf = std::numeric_limits<float>::infinity();
  best->assign(num_queries, -1);
  best_dist->assign(num_queries, kInf);
  second_dist->assign(num_queries, kInf);
  const int n = size();
  // Bit j set once candidate j was collected for the current query: n bits (1 KiB at 8192
  // features) stay in L1, where an int per descriptor (32 KiB) missed it on every lookup.
  // Cleared after each query through its candidates (the words they set), not as a whole.
  std::vector<uint64_t> seen((static_cast<size_t>(n) + 63) / 64, 0);
  // Candidates as (Hamming distance << 32 | index): sorting them ranks by distance, ties by
  // index. Written through a raw pointer into a buffer sized for the query's buckets (the
  // capacity check of push_back and the spilled loop state cost a quarter of the loop).
  std::vector<uint64_t> candidates(static_cast<size_t>(num_tables_) * 64);
  std::vector<uint64_t> ties;
  uint16_t hist[kCodeBits + 1];
  uint64_t* const seen_words = seen.data();
  for (int q = 0; q < num_queries; ++q) {
    const int i = rows ? (*rows)[q] : q;
    const uint64_t* code = &queries.codes_[2 * static_cast<size_t>(i)];
    const uint64_t c0 = code[0], c1 = code[1];
    const uint16_t* query_buckets = &queries.bucket_of_[static_cast<size_t>(i) * num_tables_];
    size_t most = 0;  // candidates at most: the sizes of the query's buckets
    for (int t = 0; t < num_tables_; ++t) {
      const int* start = &bucket_start_[static_cast<size_t>(t) * (num_buckets_ + 1)];
      const int key = query_buckets[t] & mask;
      most += static_cast<size_t>(start[key + 1] - start[key]);
    }
    if (candidates.size() < most) candidates.resize(most);
    uint64_t* out = candidates.data();
    size_t count = 0;
    std::fill(hist, hist + kCodeBits + 1, 0);
    for (int t = 0; t < num_tables_; ++t) {
      const int key = query_buckets[t] & mask;
      const int* start = &bucket_start_[static_cast<size_t>(t) * (num_buckets_ + 1)];
      const int* members = &bucket_members_[static_cast<size_t>(t) * n];
      const uint64_t* member_codes = &bucket_codes_[2 * static_cast<size_t>(t) * n];
      const int end = start[key + 1];
      for (int m = start[key]; m < end; ++m) {
        // Without a branch on whether j was seen (a duplicate is written and not counted).
        const int j = members[m];
        const uint64_t word = seen_words[j >> 6];
        const uint64_t fresh = ((word >> (j & 63)) & 1) ^ 1;
        seen_words[j >> 6] = word | uint64_t(1) << (j & 63);
        const uint64_t d = static_cast<uint64_t>(__builtin_popcountll(c0 ^ member_codes[2 * static_cast<size_t>(m)]) +
                                                 __builtin_popcountll(c1 ^ member_codes[2 * static_cast<size_t>(m) + 1]));
        hist[d] = static_cast<uint16_t>(hist[d] + fresh);
        out[count] = d << 32 | uint32_t(j);
        count += fresh;
      }
    }
    for (size_t c = 0; c < count; ++c) seen_words[(out[c] & 0xffffffffu) >> 6] = 0;
    const size_t k = SelectSmallest(num_reranked_, hist, out, count, &ties);
    // The reranked rows are scattered over the image's descriptors (1 MiB at 8192): their
    // loads are issued together before the distances need them.
    for (size_t c = 0; c < k; ++c) {
      const uint8_t* row = descriptors_.ptr<uint8_t>(static_cast<int>(candidates[c] & 0xffffffffu));
      __builtin_prefetch(row);
      __builtin_prefetch(row + 64);
    }
    int d1 = std::numeric_limits<int>::max(), d2 = d1, j1 = -1;
    const uint8_t* qd = queries.descriptors_.ptr<uint8_t>(i);
    for (size_t c = 0; c < k; ++c) {
      const int j = static_cast<int>(candidates[c] & 0xffffffffu);
      const int d = SquaredL2(qd, descriptors_.ptr<uint8_t>(j));
      if (d < d1 || (d == d1 && j < j1)) {
        d2 = d1;
        d1 = d;
        j1 = j;
      } else if (d < d2) {
        d2 = d;
      }
    }
    (*best)[q] = j1;
    if (j1 >= 0) (*best_dist)[q] = std::sqrt(static_cast<float>(d1));
    if (k >= 2) (*second_dist)[q] = std::sqrt(static_cast<float>(d2));
  }
}

std::string CascadeHashingOptions::Check() const {
  if (const std::string m = CheckRanges(*this, "matching.descriptors.cascade_hashing"); !m.empty()) return m;
  return "";
}

}  // namespace pgba
