// Connectivity of the view graph and of the triplet graph.
//
// Two triplets are adjacent when they share two images: a shared pair fixes their relative
// scale, a single shared image does not (the second triplet could still be scaled about that
// image). The pointless global BA, whose unknowns include one similarity per triplet, is
// therefore only well posed on a component of this edge-adjacency graph, and so is the
// triplet translation averaging: each component is initialised and adjusted as a model of
// its own.
#pragma once

#include <cstdint>
#include <set>
#include <vector>

#include "pgba/scene/view_graph.h"

namespace pgba {

// Disjoint sets with path halving and union by size; deterministic.
class UnionFind {
 public:
  explicit UnionFind(int n);
  int Find(int a);
  // Returns false if a and b were already in the same set.
  bool Union(int a, int b);
  int SizeOf(int a) { return size_[Find(a)]; }

 private:
  std::vector<int> parent_;
  std::vector<int> size_;
};

// An undirected weighted edge between nodes i and j.
struct WeightedEdge {
  int i = 0;
  int j = 0;
  double weight = 0.0;
};

// Kruskal's maximum spanning forest: indices into `edges` of the kept edges, heaviest first
// (ties broken by index, so the result is deterministic).
std::vector<int> MaximumSpanningForest(int num_nodes, const std::vector<WeightedEdge>& edges);

// Images of the largest connected component of the graph whose edges are the pairs (ties:
// the component containing the smallest image id).
std::set<uint32_t> LargestViewGraphComponent(const std::vector<TwoViewGeometry>& pairs);

// Every component of the triplet graph with edge adjacency (see above) as the indices
// (ascending) of its triplets, largest first: covering the most images, then the most
// triplets, then the smallest triplet index. Triplets with repeated images are in none.
std::vector<std::vector<int>> TripletComponents(const std::vector<LocalMotion>& triplets);

// Indices (ascending) of the triplets forming the largest component of the triplet graph with
// edge adjacency (see above), largest = covering the most images; ties: the component with
// the most triplets, then the smallest triplet index. Triplets with repeated images are
// ignored. Empty if there is no valid triplet.
std::vector<int> LargestTripletComponent(const std::vector<LocalMotion>& triplets);

// Images covered by the given triplets.
std::set<uint32_t> ImagesOfTriplets(const std::vector<LocalMotion>& triplets, const std::vector<int>& indices);

}  // namespace pgba
