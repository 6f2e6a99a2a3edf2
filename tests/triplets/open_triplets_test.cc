// Open triplets (TripletOptions::open_triplets): when the skip pairs of a chain do not
// verify there are no triangles, and the chain is only held together by paths a - b - c of
// two verified pairs. Checked on a synthetic orbit whose view graph is cut down to the
// consecutive pairs: every image is covered by one connected triplet graph, and each open
// triplet's local geometry (rotations and, above all, its measured baseline ratio) agrees
// with the ground truth. On the full view graph no open triplet is even tried.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <cstdlib>

#include "pgba/geometry/rotation.h"
#include "synthetic/synthetic_scene.h"
#include "triplets/triplet_selection.h"
#include "triplets/triplets.h"
#include "triplets/pair_estimation.h"

namespace pgba {
namespace {

constexpr int kImages = 40;  // 9 degrees apart on the orbit: every neighbour pair verifies

SyntheticScene Orbit(int num_images) {
  SyntheticOptions so;
  so.scenario = SyntheticScenario::kOrbit;
  so.seed = 3;
  so.noise_px = 0.5;
  so.outlier_fraction = 0.02;
  so.num_images = num_images;
  so.num_points = 8000;  // the default density of the 70-image orbit
  return GenerateSyntheticScene(so);
}

struct TripletErrors {
  std::vector<double> rotation_deg;  // relative rotations 0 -> 1 and 0 -> 2
  std::vector<double> ratio;         // |C2 - C0| / |C1 - C0| against the truth, relative
};

// Gauge-free comparison of each triplet's local frame with the ground truth: the scale of
// the local frame is |C1 - C0| = 1, so the ratio of the two baselines from view 0 is what
// a triplet measures beyond its three pair directions.
TripletErrors ErrorsAgainstTruth(const std::vector<LocalMotion>& triplets, const SyntheticScene& scene) {
  TripletErrors e;
  for (const LocalMotion& t : triplets) {
    std::array<Pose, 3> gt;
    for (int k = 0; k < 3; ++k) gt[k] = scene.gt.images.at(t.image_ids[k]).pose;
    for (int k = 1; k < 3; ++k)
      e.rotation_deg.push_back(RotationAngleDeg(t.local_poses[k].R() * t.local_poses[0].R().transpose(),
                                                gt[k].R() * gt[0].R().transpose()));
    const double local = (t.local_poses[2].C() - t.local_poses[0].C()).norm() /
                         (t.local_poses[1].C() - t.local_poses[0].C()).norm();
    const double truth = (gt[2].C() - gt[0].C()).norm() / (gt[1].C() - gt[0].C()).norm();
    e.ratio.push_back(std::abs(local / truth - 1.0));
  }
  return e;
}

double Median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}
double Max(const std::vector<double>& v) { return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end()); }

std::vector<TwoViewGeometry> ConsecutivePairsOnly(const std::vector<TwoViewGeometry>& pairs) {
  std::vector<TwoViewGeometry> chain;
  for (const TwoViewGeometry& g : pairs)
    if (std::abs(static_cast<int>(g.image_id1) - static_cast<int>(g.image_id2)) == 1) chain.push_back(g);
  return chain;
}

TEST(OpenTriplets, ChainWithoutSkipPairsIsBridgedAndKeepsItsScale) {
  const SyntheticScene scene = Orbit(kImages);
  const std::vector<TwoViewGeometry> chain = ConsecutivePairsOnly(EstimatePairs(scene.input, PairOptions{}));
  ASSERT_EQ(chain.size(), kImages - 1u);  // the orbit is an open path 1 - 2 - ... - N here
  ASSERT_TRUE(EnumerateTriangles(chain).empty());

  TripletStats stats;
  const std::vector<LocalMotion> triplets = BuildTriplets(scene.input, chain, TripletOptions{}, &stats);
  EXPECT_EQ(stats.images_covered, kImages);
  EXPECT_EQ(stats.triplet_graph_components, 1);
  EXPECT_EQ(stats.open_selected, static_cast<int>(triplets.size()));
  ASSERT_GE(triplets.size(), kImages - 2u);  // every consecutive (i, i+1, i+2) is needed for one component

  const TripletErrors open = ErrorsAgainstTruth(triplets, scene);
  std::cout << "open triplets: rotation error median " << Median(open.rotation_deg) << " max "
            << Max(open.rotation_deg) << " deg; baseline ratio error median " << Median(open.ratio) << " max "
            << Max(open.ratio) << "\n";
  // The bar is set by what closed triplets reach on the same scene (second test): 0.5 px
  // noise gives a few hundredths of a degree typically, a few tenths on the weakest.
  EXPECT_LT(Median(open.rotation_deg), 0.1);
  EXPECT_LT(Max(open.rotation_deg), 0.5);
  EXPECT_LT(Median(open.ratio), 0.005);
  EXPECT_LT(Max(open.ratio), 0.02);
}

TEST(OpenTriplets, NotTriedWhereTrianglesAlreadyConnectEverything) {
  const SyntheticScene scene = Orbit(kImages);
  TripletStats stats;
  const std::vector<LocalMotion> triplets =
      BuildTriplets(scene.input, EstimatePairs(scene.input, PairOptions{}), TripletOptions{}, &stats);
  EXPECT_EQ(stats.triplet_graph_components, 1);
  EXPECT_EQ(stats.images_covered, kImages);
  EXPECT_EQ(stats.open_candidates, 0);
  EXPECT_EQ(stats.open_selected, 0);
  const TripletErrors closed = ErrorsAgainstTruth(triplets, scene);
  std::cout << "closed triplets: rotation error median " << Median(closed.rotation_deg) << " max "
            << Max(closed.rotation_deg) << " deg; baseline ratio error median " << Median(closed.ratio) << " max "
            << Max(closed.ratio) << "\n";
}

TEST(OpenTriplets, DisabledLeavesTheChainUncovered) {
  const SyntheticScene scene = Orbit(kImages);
  const std::vector<TwoViewGeometry> chain = ConsecutivePairsOnly(EstimatePairs(scene.input, PairOptions{}));
  TripletOptions options;
  options.open_triplets = false;
  TripletStats stats;
  EXPECT_TRUE(BuildTriplets(scene.input, chain, options, &stats).empty());
  EXPECT_EQ(stats.open_candidates, 0);
}

}  // namespace
}  // namespace pgba
