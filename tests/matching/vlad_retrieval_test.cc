// VLAD retrieval (modules/matching/vlad_retrieval.h) on a small rendered aerial block
// (modules/synthetic/aerial_block.h): the pairs it selects from the images' own SIFT
// descriptors are judged against the pairs whose true ground footprints overlap, a truth
// computed from the poses alone. Retrieval must find nearly all strongly overlapping pairs,
// few of its pairs may be disjoint, the count stays within n x neighbors, and the result
// does not depend on the number of threads.
#include "matching/vlad_retrieval.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <iostream>
#include <opencv2/imgproc.hpp>
#include <set>

#include "features/sift_extractor.h"
#include "matching/pair_selection.h"
#include "modules/synthetic/aerial_block.h"

namespace pgba {
namespace {

using Pair = std::pair<uint32_t, uint32_t>;

struct BlockFeatures {
  AerialBlock block;
  std::vector<cv::Mat> descriptors;
};

// 40 images 512 x 384 in 4 strips (75% forward, 50% side overlap), up to 1500 features each.
const BlockFeatures& SmallBlock() {
  static const BlockFeatures* features = [] {
    AerialBlockOptions o = DefaultAerialBlockOptions();
    o.image.num_images = 40;
    o.image.width = 512;
    o.image.height = 384;
    o.strips = 4;
    o.ground_sample_m = 0.2;  // the same ground as 1024 x 768 at 0.1 m, half the pixels
    auto* f = new BlockFeatures{MakeAerialBlock(o), {}};
    f->descriptors.resize(f->block.gt.images.size());
    SiftOptions sift;
    sift.max_features = 1500;
    tbb::parallel_for(size_t(0), f->descriptors.size(), [&](size_t k) {
      cv::Mat gray;
      cv::cvtColor(RenderAerialImage(f->block, o, k), gray, cv::COLOR_BGR2GRAY);
      f->descriptors[k] = ExtractSift(gray, sift).descriptors;
    });
    return f;
  }();
  return *features;
}

// The vocabulary from every second descriptor (~30k of ~60k; the default budget of 100k
// would take them all): keeps the tests fast and goes through the sampling stride.
VladOptions TestVlad() {
  VladOptions o;
  o.max_training_descriptors = 30000;
  return o;
}

double Recall(const std::vector<Pair>& truth, const std::set<Pair>& found) {
  size_t hit = 0;
  for (const Pair& p : truth) hit += found.count(p);
  return truth.empty() ? 1.0 : double(hit) / truth.size();
}

// Judged over five vocabularies (k-means seeds 0-4), not one: which pairs are chosen moves
// with the vocabulary. Measured on this block (10 seeds each), disjoint pairs at k 10:
// 15-22 with OpenCV's SIFT (its seed 5 at the bar of one tenth), 14-23 with pgba's (seeds
// 0 and 5 above it); means 18.9 and 19.8. Recall at k 5: 0.968-1.0 and 0.952-0.984, means
// 0.981 and 0.974. One seed's count was a draw from that spread, not a property of the
// retrieval; the mean of five has a fifth of the variance (sd ~1.1 pairs instead of ~2.4),
// and the bars are the ones the single seed had.
TEST(VladRetrieval, FindsTheTrulyOverlappingPairsOfAnAerialBlockWithinNTimesK) {
  const BlockFeatures& f = SmallBlock();
  const size_t n = f.descriptors.size();
  ASSERT_EQ(n, 40u);
  for (const cv::Mat& d : f.descriptors) ASSERT_GT(d.rows, 1000);

  const std::vector<Pair> strong = OverlappingPairs(f.block, 0.5);  // neighbours along a strip, across strips
  const std::vector<Pair> any = OverlappingPairs(f.block, 0.01);
  const std::set<Pair> any_set(any.begin(), any.end());
  constexpr int kSeeds = 5;
  for (int k : {5, 10}) {
    double recall_sum = 0, disjoint_fraction_sum = 0;
    for (int seed = 0; seed < kSeeds; ++seed) {
      VladOptions o = TestVlad();
      o.neighbors = k;
      o.seed = seed;
      const std::vector<Pair> pairs = RetrievalPairs(f.descriptors, o);
      // Bounded: each image adds at most k pairs (fewer where two images chose each other).
      EXPECT_LE(pairs.size(), n * k);
      EXPECT_GE(pairs.size(), n * k / 2);
      EXPECT_TRUE(std::is_sorted(pairs.begin(), pairs.end()));
      std::vector<int> degree(n, 0);
      for (const auto& [i, j] : pairs) {
        ASSERT_LT(i, j);
        ASSERT_LT(j, n);
        ++degree[i], ++degree[j];
      }
      for (size_t i = 0; i < n; ++i) EXPECT_GE(degree[i], k) << "image " << i << " lost its own top-k";
      const std::set<Pair> found(pairs.begin(), pairs.end());
      const double recall = Recall(strong, found);
      size_t disjoint = 0;
      for (const Pair& p : pairs) disjoint += !any_set.count(p);
      std::cout << "k " << k << " seed " << seed << ": " << pairs.size() << " pairs, recall of the "
                << strong.size() << " pairs overlapping >= 50%: " << recall << ", of the " << any.size()
                << " overlapping at all: " << Recall(any, found) << ", disjoint pairs " << disjoint << std::endl;
      recall_sum += recall;
      disjoint_fraction_sum += double(disjoint) / pairs.size();
    }
    // Bars as for one seed (k 5: recall 0.984 of 62 with no disjoint pair at OpenCV's seed 0;
    // k 10: recall 1.0, 17 of 226 disjoint: the top 10 reach past the ~3 neighbours per
    // image that overlap >= 50% into images that look alike without sharing ground).
    EXPECT_GE(recall_sum / kSeeds, k == 5 ? 0.95 : 0.99);
    EXPECT_LE(disjoint_fraction_sum / kSeeds, k == 5 ? 0.02 : 0.1);
  }
}

TEST(VladRetrieval, SamePairsWithOneThreadAsWithTwo) {
  const BlockFeatures& f = SmallBlock();
  VladOptions o = TestVlad();
  o.neighbors = 6;
  std::vector<Pair> one, two;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one = RetrievalPairs(f.descriptors, o);
  }
  {
    // Through the pair selection, which validates its options, on two threads.
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 2);
    PairSelectionOptions sel;
    sel.method = "retrieval";
    sel.vlad = o;
    two = SelectPairs(f.descriptors, sel);
  }
  EXPECT_EQ(one, two);
}

}  // namespace
}  // namespace pgba
