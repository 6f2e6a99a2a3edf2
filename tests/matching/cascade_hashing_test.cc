// Cascade hashing against a known truth: image 2 holds image 1's descriptors, shuffled, with
// noise, among as many unrelated ones. Every noisy copy is far closer to its original than
// to anything else, so the exact answer is the shuffle, and the hashing's recall can be
// predicted: a noisy copy at angle a from its original differs in each code bit with
// probability a / pi, so it shares one of 6 buckets of 8 bits with probability
// 1 - (1 - (1 - a/pi)^8)^6, > 0.99 here.
#include "matching/cascade_hashing.h"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <numeric>
#include <random>

#include "matching/descriptor_matcher.h"
#include "pgba/util/error.h"

namespace pgba {
namespace {

struct SyntheticPair {
  cv::Mat d1, d2;
  std::vector<int> truth;  // feature of image 1 -> its noisy copy in image 2
};

// Non-negative unit vectors scaled to 512 (the RootSIFT quantisation), rounded to uint8.
void RandomDescriptor(std::mt19937& rng, uint8_t* out) {
  std::exponential_distribution<double> e(1.0);
  double v[128], norm = 0.0;
  for (double& x : v) {
    x = e(rng);
    norm += x * x;
  }
  for (int k = 0; k < 128; ++k) out[k] = static_cast<uint8_t>(std::min(255.0, std::round(512.0 * v[k] / std::sqrt(norm))));
}

SyntheticPair MakePair(int n, double noise, uint32_t seed) {
  std::mt19937 rng(seed);
  SyntheticPair p;
  p.d1.create(n, 128, CV_8U);
  p.d2.create(2 * n, 128, CV_8U);
  for (int i = 0; i < n; ++i) RandomDescriptor(rng, p.d1.ptr<uint8_t>(i));
  std::vector<int> slot(2 * n);
  std::iota(slot.begin(), slot.end(), 0);
  std::shuffle(slot.begin(), slot.end(), rng);
  std::normal_distribution<double> g(0.0, noise);
  p.truth.resize(n);
  for (int i = 0; i < n; ++i) {
    p.truth[i] = slot[i];
    for (int k = 0; k < 128; ++k)
      p.d2.at<uint8_t>(slot[i], k) =
          static_cast<uint8_t>(std::clamp(std::round(p.d1.at<uint8_t>(i, k) + g(rng)), 0.0, 255.0));
  }
  for (int i = n; i < 2 * n; ++i) RandomDescriptor(rng, p.d2.ptr<uint8_t>(slot[i]));
  return p;
}

std::vector<std::pair<uint32_t, uint32_t>> Match(const SyntheticPair& p, const DescriptorMatchOptions& o) {
  const CascadeHasher hasher(MeanDescriptor({p.d1, p.d2}), o.cascade_hashing, 7);
  const DescriptorIndex a(p.d1, o, 1, &hasher), b(p.d2, o, 2, &hasher);
  return MatchDescriptors(a, b, o);
}

TEST(CascadeHashing, FindsTheTrueNeighboursAtThePredictedRecall) {
  const SyntheticPair p = MakePair(4000, 6.0, 3);
  DescriptorMatchOptions o;
  ASSERT_EQ(o.method, "cascade_hashing");
  const auto matches = Match(p, o);
  size_t correct = 0;
  for (const auto& [i, j] : matches) correct += static_cast<int>(j) == p.truth[i];
  EXPECT_EQ(correct, matches.size());  // no distractor is ever closer than the true copy
  EXPECT_GE(matches.size(), 0.99 * p.truth.size());

  // The same recall as the kd-forest (32 checks) on the same data, and a deterministic result.
  DescriptorMatchOptions kd = o;
  kd.method = "kdtree";
  const auto kd_matches = Match(p, kd);
  EXPECT_GE(matches.size() + p.truth.size() / 100, kd_matches.size());
  EXPECT_EQ(Match(p, o), matches);
}

TEST(CascadeHashing, BucketCodesPredictRecall) {
  // One table of 8 bits and an L2 shortlist holding the whole bucket: a copy is found iff
  // its bucket code equals its original's, with probability (1 - a/pi)^8 for the angle a
  // between the two centred descriptors (random hyperplanes through the mean).
  const SyntheticPair p = MakePair(4000, 6.0, 5);
  DescriptorMatchOptions o;
  o.cross_check = false;
  o.cascade_hashing.num_tables = 1;
  o.cascade_hashing.target_bucket_size = 16;  // 8000 descriptors: all 8 bits, 31 per bucket
  o.cascade_hashing.num_reranked = 1000;
  const auto matches = Match(p, o);
  cv::Mat mean;
  MeanDescriptor({p.d1, p.d2}).convertTo(mean, CV_64F);
  double predicted = 0.0;
  for (int i = 0; i < p.d1.rows; ++i) {
    cv::Mat a, b;
    p.d1.row(i).convertTo(a, CV_64F);
    p.d2.row(p.truth[i]).convertTo(b, CV_64F);
    a -= mean;
    b -= mean;
    const double angle = std::acos(std::clamp(a.dot(b) / (cv::norm(a) * cv::norm(b)), -1.0, 1.0));
    predicted += std::pow(1.0 - angle / CV_PI, 8);
  }
  predicted /= p.d1.rows;
  size_t correct = 0;
  for (const auto& [i, j] : matches) correct += static_cast<int>(j) == p.truth[i];
  const double recall = static_cast<double>(correct) / p.truth.size();
  // 4000 Bernoulli trials: one standard deviation of the recall is below 0.008.
  EXPECT_NEAR(recall, predicted, 0.025);
  EXPECT_LT(predicted, 0.9);  // the test is not trivially saturated
}

TEST(CascadeHashing, ShortBucketCodesKeepRecallOnFewFeatures) {
  // 230 features per image, as on the weakly textured dino ring: with the full 8-bit codes
  // a bucket holds ~1 descriptor and a query meets a handful of candidates; codes cut to
  // ~32 descriptors per bucket find the copies as well as the kd-forest does.
  const SyntheticPair p = MakePair(230, 10.0, 11);
  DescriptorMatchOptions o, full = o, kd = o;
  full.cascade_hashing.target_bucket_size = 1;
  kd.method = "kdtree";
  auto correct = [&](const DescriptorMatchOptions& opt) {
    size_t n = 0;
    for (const auto& [i, j] : Match(p, opt)) n += static_cast<int>(j) == p.truth[i];
    return n;
  };
  const size_t adaptive = correct(o), fixed = correct(full), forest = correct(kd);
  std::cout << "of 230: adaptive " << adaptive << ", 8 bits " << fixed << ", kd-forest " << forest << std::endl;
  EXPECT_GE(adaptive, 225u);
  EXPECT_GE(adaptive, forest);
  EXPECT_GT(adaptive, fixed);
}

TEST(CascadeHashing, RejectsOptionsOutOfRange) {
  CascadeHashingOptions o;
  o.bits_per_bucket = 17;
  EXPECT_THROW(ValidateCascadeHashingOptions(o), InputError);
  o = {};
  o.num_reranked = 1;
  EXPECT_THROW(ValidateCascadeHashingOptions(o), InputError);
  DescriptorMatchOptions d;
  d.method = "brute";
  try {
    ValidateDescriptorMatchOptions(d);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("matching.descriptors.method"), std::string::npos);
  }
}

}  // namespace
}  // namespace pgba
