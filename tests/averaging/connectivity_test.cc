#include "averaging/connectivity.h"

#include <gtest/gtest.h>

namespace pgba {
namespace {

LocalMotion T(uint32_t a, uint32_t b, uint32_t c) {
  LocalMotion t;
  t.image_ids = {a, b, c};
  return t;
}

TwoViewGeometry P(uint32_t a, uint32_t b) {
  TwoViewGeometry p;
  p.image_id1 = a;
  p.image_id2 = b;
  return p;
}

TEST(Connectivity, LargestViewGraphComponent) {
  // {1,2,3,4} and {10,11}, plus 20-21-22 (three images, smaller than four).
  const std::vector<TwoViewGeometry> pairs = {P(1, 2), P(10, 11), P(3, 2), P(20, 21), P(4, 3), P(21, 22)};
  EXPECT_EQ(LargestViewGraphComponent(pairs), (std::set<uint32_t>{1, 2, 3, 4}));
  // Ties: the component holding the smallest image id.
  EXPECT_EQ(LargestViewGraphComponent({P(7, 8), P(3, 5)}), (std::set<uint32_t>{3, 5}));
  EXPECT_TRUE(LargestViewGraphComponent({}).empty());
}

TEST(Connectivity, TripletsMustShareAPair) {
  // (1,2,3)-(2,3,4)-(3,4,5) share pairs; (5,6,7) touches them in image 5 only; (8,9,10) is
  // apart; (11,11,12) is invalid.
  const std::vector<LocalMotion> triplets = {T(5, 6, 7), T(1, 2, 3), T(8, 9, 10), T(4, 3, 2), T(11, 11, 12), T(3, 5, 4)};
  const std::vector<int> kept = LargestTripletComponent(triplets);
  EXPECT_EQ(kept, (std::vector<int>{1, 3, 5}));
  EXPECT_EQ(ImagesOfTriplets(triplets, kept), (std::set<uint32_t>{1, 2, 3, 4, 5}));
  EXPECT_TRUE(LargestTripletComponent({}).empty());
  EXPECT_TRUE(LargestTripletComponent({T(1, 1, 2)}).empty());
}

TEST(Connectivity, LargestTripletComponentCountsImages) {
  // Component A: 2 triplets over 4 images; component B: 3 triplets over 5 images.
  const std::vector<LocalMotion> triplets = {T(1, 2, 3), T(2, 3, 4), T(10, 11, 12), T(11, 12, 13), T(12, 13, 14)};
  EXPECT_EQ(LargestTripletComponent(triplets), (std::vector<int>{2, 3, 4}));
}

TEST(Connectivity, EveryTripletComponentLargestFirst) {
  // {1..5} over three triplets (one sharing only image 5 with them forms its own component
  // {5,6,7}); {8,9,10}; (11,11,12) is in none. Equal image counts: more triplets first, then
  // the smaller first index.
  const std::vector<LocalMotion> triplets = {T(5, 6, 7), T(1, 2, 3), T(8, 9, 10), T(4, 3, 2), T(11, 11, 12), T(3, 5, 4)};
  const std::vector<std::vector<int>> components = TripletComponents(triplets);
  ASSERT_EQ(components.size(), 3u);
  EXPECT_EQ(components[0], (std::vector<int>{1, 3, 5}));
  EXPECT_EQ(components[1], (std::vector<int>{0}));
  EXPECT_EQ(components[2], (std::vector<int>{2}));
  EXPECT_EQ(components[0], LargestTripletComponent(triplets));
  EXPECT_TRUE(TripletComponents({}).empty());
  EXPECT_TRUE(TripletComponents({T(1, 1, 2)}).empty());
}

TEST(Connectivity, MaximumSpanningForest) {
  // Square 0-1-2-3 with a diagonal; the lightest cycle edges are left out; node 4 isolated.
  const std::vector<WeightedEdge> edges = {{0, 1, 5}, {1, 2, 1}, {2, 3, 4}, {3, 0, 3}, {0, 2, 2}, {1, 1, 9}};
  const std::vector<int> kept = MaximumSpanningForest(5, edges);
  EXPECT_EQ(kept, (std::vector<int>{0, 2, 3}));
}

TEST(Connectivity, UnionFind) {
  UnionFind uf(5);
  EXPECT_TRUE(uf.Union(0, 1));
  EXPECT_TRUE(uf.Union(3, 4));
  EXPECT_FALSE(uf.Union(1, 0));
  EXPECT_TRUE(uf.Union(1, 4));
  EXPECT_EQ(uf.Find(0), uf.Find(3));
  EXPECT_NE(uf.Find(2), uf.Find(0));
  EXPECT_EQ(uf.SizeOf(4), 4);
}

}  // namespace
}  // namespace pgba
