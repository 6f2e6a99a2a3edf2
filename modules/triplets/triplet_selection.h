// Triplet selection: bounds the number of triplets on highly overlapping image sets while
// keeping every image covered and the triplet graph connected.
//
// Two triplets are adjacent in the triplet graph when they share an image pair (an edge of
// the view graph): a shared pair carries the relative scale from one triplet to the other,
// a single shared image does not. Selection works in three steps:
//   1. Order the candidates best first (score, then image ids).
//   2. Greedy cap: take the locked triplets, then a triplet if any of its images is still in
//      fewer than K selected triplets. Every image of a candidate therefore ends in >= min(K, its candidates)
//      triplets (coverage), and at most K x #images triplets are taken.
//   3. Connectivity repair: while a connected component of the candidate graph holds
//      several selected components, a 0-1 breadth-first search from the largest one (cost
//      1 per unselected triplet traversed) finds the shortest bridge of unselected
//      triplets to another selected component, and selects it.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "pgba/scene/local_motion.h"

namespace pgba {

// The three image ids of a triplet (a motion of three views), in its order.
inline std::array<uint32_t, 3> TripletImageIds(const LocalMotion& triplet) {
  return {triplet.image_ids.at(0), triplet.image_ids.at(1), triplet.image_ids.at(2)};
}

struct TripletCandidate {
  std::array<uint32_t, 3> image_ids{};  // sorted ascending
  double score = 0.0;                   // higher is better
  bool excluded = false;                // not available (failed estimation)
  bool locked = false;                  // selected in any case (kept from an earlier round)
};

// Selected candidate indices, ascending. max_per_image <= 0 selects every available
// candidate.
std::vector<size_t> SelectTriplets(const std::vector<TripletCandidate>& candidates, int max_per_image);

// Connected components of the triplet graph (adjacency = a shared image pair): one label
// per triplet, labels 0..n-1 in order of first appearance.
std::vector<int> TripletGraphComponents(const std::vector<std::array<uint32_t, 3>>& triplets, int* num_components);

}  // namespace pgba
