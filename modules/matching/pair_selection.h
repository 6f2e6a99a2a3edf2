// Which image pairs to match.
//   exhaustive  every pair: n(n-1)/2. Best for unordered sets up to a few hundred images.
//   sequential  each image with the next `window` images in name order (video, or
//               acquisitions along a path); `loop` also wraps the window around the end,
//               for closed rings.
//   retrieval   each image with its `neighbors` most similar images by a VLAD global
//               descriptor (vlad_retrieval.h): for large unordered sets, between
//               n * neighbors / 2 and n * neighbors pairs (a pair both images chose counts
//               once) instead of n^2 / 2, so matching grows linearly with n. Measured on
//               rendered aerial blocks (tests/matching/vlad_retrieval_test.cc;
//               bench/thousand_photos.sh, docs/benchmarks.md "A thousand photos"):
//               neighbors 10 finds every pair whose footprints overlap by >= 50%.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "matching/vlad_retrieval.h"

namespace pgba {

struct PairSelectionOptions {
  std::string method = "exhaustive";  // exhaustive | sequential | retrieval
  int window = 10;                    // sequential: neighbours after each image
  bool loop = false;                  // sequential: also pair the last images with the first
  VladOptions vlad;                   // retrieval
  // Empty when valid, else one line naming the first field out of its valid range (the
  // ranges of io/option_ranges.cc) or breaking a rule between fields.
  std::string Check() const;
};
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(PairSelectionOptions, method, window, loop, vlad)

using ImagePair = std::pair<uint32_t, uint32_t>;  // (smaller index, larger index)

// Pairs of indices into an image list of size n (sorted by name), each once, first < second,
// in lexicographic order.
std::vector<ImagePair> ExhaustivePairs(int n);
std::vector<ImagePair> SequentialPairs(int n, int window, bool loop);

// Dispatches on options.method; `descriptors` (one CV_8U matrix per image) are only used by
// retrieval. InputError for an unknown method or a window < 1.
std::vector<ImagePair> SelectPairs(const std::vector<cv::Mat>& descriptors, const PairSelectionOptions& options);

}  // namespace pgba
