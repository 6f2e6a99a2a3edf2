#include "matching/pair_selection.h"

#include <set>

#include "pgba/io/option_ranges.h"
#include "pgba/util/error.h"

namespace pgba {

std::vector<ImagePair> ExhaustivePairs(int n) {
  std::vector<ImagePair> pairs;
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) pairs.emplace_back(i, j);
  return pairs;
}

std::vector<ImagePair> SequentialPairs(int n, int window, bool loop) {
  std::set<ImagePair> pairs;
  for (int i = 0; i < n; ++i)
    for (int d = 1; d <= window; ++d) {
      int j = i + d;
      if (j >= n) {
        if (!loop) break;
        j %= n;  // a window longer than the ring wraps more than once (j - n may still be >= n)
      }
      if (j != i) pairs.emplace(std::min(i, j), std::max(i, j));
    }
  return {pairs.begin(), pairs.end()};
}

std::vector<ImagePair> SelectPairs(const std::vector<cv::Mat>& descriptors, const PairSelectionOptions& options) {
  const int n = static_cast<int>(descriptors.size());
  if (options.method == "exhaustive") return ExhaustivePairs(n);
  if (options.method == "sequential") {
    if (options.window < 1) ThrowInputError("--window", 0, "must be at least 1");
    return SequentialPairs(n, options.window, options.loop);
  }
  if (options.method == "retrieval") {
    if (options.vlad.neighbors < 1 || options.vlad.num_words < 1)
      ThrowInputError("--neighbors", 0, "retrieval needs neighbors >= 1 and num_words >= 1");
    return RetrievalPairs(descriptors, options.vlad);
  }
  ThrowInputError("--pairs", 0, "unknown pair selection '" + options.method + "' (exhaustive, sequential, retrieval)");
}

std::string PairSelectionOptions::Check() const {
  if (const std::string m = CheckRanges(*this, "matching.pairs"); !m.empty()) return m;
  return "";
}

}  // namespace pgba
