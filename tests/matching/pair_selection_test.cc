// Sequential and loop pair selection (pair_selection.h) against their definition, written
// here independently of the code: in name order, images i < j are paired iff
//   sequential:        j - i <= window
//   sequential + loop: the distance around the ring min(j - i, n - (j - i)) <= window,
// every pair once, (smaller, larger), lexicographic; exhaustive is every pair. Checked over
// every n up to 13 and window up to n + 1 (windows past the ring's half give every pair),
// plus closed-form counts, and the bad options that SelectPairs refuses.
#include "matching/pair_selection.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "pgba/util/error.h"

namespace pgba {
namespace {

std::vector<ImagePair> ByDefinition(int n, int window, bool loop) {
  std::vector<ImagePair> pairs;
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) {
      const int d = loop ? std::min(j - i, n - (j - i)) : j - i;
      if (d <= window) pairs.emplace_back(i, j);
    }
  return pairs;  // generated in lexicographic order
}

TEST(PairSelection, SequentialAndLoopPairsAreThoseWithinTheWindowInNameOrder) {
  for (int n = 0; n <= 13; ++n)
    for (int window = 1; window <= n + 1; ++window)
      for (const bool loop : {false, true}) {
        const std::vector<ImagePair> pairs = SequentialPairs(n, window, loop);
        EXPECT_EQ(pairs, ByDefinition(n, window, loop)) << "n " << n << " window " << window << " loop " << loop;
        EXPECT_TRUE(std::is_sorted(pairs.begin(), pairs.end()));
        EXPECT_EQ(std::set<ImagePair>(pairs.begin(), pairs.end()).size(), pairs.size());
      }
}

TEST(PairSelection, PairCountsInClosedForm) {
  // A chain of n with window w < n: each of the first n - w images has w successors, the last
  // w images w - 1, ..., 0: n w - w (w + 1) / 2 pairs. A ring with 2 w < n: every image has w
  // successors around it, n w pairs; with 2 w >= n: every pair, n (n - 1) / 2.
  for (const int n : {5, 10, 36, 101})
    for (const int w : {1, 2, 4})
      if (w < n) {
        EXPECT_EQ(SequentialPairs(n, w, false).size(), static_cast<size_t>(n * w - w * (w + 1) / 2)) << n << " " << w;
        EXPECT_EQ(SequentialPairs(n, w, true).size(), static_cast<size_t>(2 * w < n ? n * w : n * (n - 1) / 2))
            << n << " " << w;
      }
  // The loop adds exactly the pairs across the seam: with n = 10, w = 2, (0, 8), (0, 9), (1, 9).
  const std::vector<ImagePair> chain = SequentialPairs(10, 2, false), ring = SequentialPairs(10, 2, true);
  std::vector<ImagePair> added;
  std::set_difference(ring.begin(), ring.end(), chain.begin(), chain.end(), std::back_inserter(added));
  EXPECT_EQ(added, (std::vector<ImagePair>{{0, 8}, {0, 9}, {1, 9}}));
  EXPECT_EQ(ExhaustivePairs(10), ByDefinition(10, 10, false));
  EXPECT_EQ(ExhaustivePairs(10).size(), 45u);
}

TEST(PairSelection, SelectPairsDispatchesAndRefusesBadOptions) {
  const std::vector<cv::Mat> descriptors(7);  // only their count matters here
  PairSelectionOptions o;
  EXPECT_EQ(SelectPairs(descriptors, o), ByDefinition(7, 7, false));
  o.method = "sequential";
  o.window = 2;
  o.loop = true;
  EXPECT_EQ(SelectPairs(descriptors, o), ByDefinition(7, 2, true));
  o.window = 0;
  EXPECT_THROW(SelectPairs(descriptors, o), InputError);
  o.method = "nearest";
  o.window = 2;
  try {
    SelectPairs(descriptors, o);
    ADD_FAILURE() << "an unknown method was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("nearest"), std::string::npos) << e.what();
  }
  o.method = "retrieval";
  o.vlad.neighbors = 0;
  EXPECT_THROW(SelectPairs(descriptors, o), InputError);
}

}  // namespace
}  // namespace pgba
