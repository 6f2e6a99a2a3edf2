// Weak pairs confirmed by a third view, against a synthetic truth: three cameras on a ring
// around the origin looking at it (23.5 degrees apart, as dino_sparse_ring), the pairs'
// relative poses from the true poses, matches that are the same scene features. A weak pair
// that is right closes its triangle and is confirmed; one whose rotation is off (dino's
// well-conditioned wrong pair: 47 degrees), whose baseline points the wrong way, or whose
// matches do not transfer into the third view, is not.
#include "matching/triplet_confirmation.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

namespace pgba {
namespace {

constexpr double kDeg = M_PI / 180.0;

struct View {
  Eigen::Matrix3d R;  // world -> camera
  Eigen::Vector3d C;  // centre
};

// Camera at angle a on a ring of radius 10 around the origin, looking at it.
View RingView(double a) {
  View v;
  v.C = Eigen::Vector3d(10 * std::sin(a), 0, -10 * std::cos(a));
  const Eigen::Vector3d z = (-v.C).normalized(), y(0, 1, 0), x = y.cross(z);
  v.R.row(0) = x;
  v.R.row(1) = y;
  v.R.row(2) = z;
  return v;
}

// The pair (a, b) as verification returns it, with `n` matches: scene feature f is feature
// f of every image.
PairEstimate TruePair(uint32_t a, uint32_t b, const View& va, const View& vb, int n) {
  PairEstimate p;
  p.image1 = a;
  p.image2 = b;
  p.R_21 = vb.R * va.R.transpose();
  p.t_21 = (-vb.R * (vb.C - va.C)).normalized() * 0.7;  // any scale: only the direction counts
  for (int f = 0; f < n; ++f) p.matches.emplace_back(f, f);
  return p;
}

class TripletConfirmation : public ::testing::Test {
 protected:
  void SetUp() override {
    for (int k = 0; k < 3; ++k) views_.push_back(RingView(k * 23.5 * kDeg));
    pairs_ = {TruePair(0, 1, views_[0], views_[1], 40), TruePair(0, 2, views_[0], views_[2], 40),
              TruePair(1, 2, views_[1], views_[2], 40)};
    pairs_[0].weak = true;
  }
  std::vector<View> views_;
  std::vector<PairEstimate> pairs_;
  TripletConfirmationOptions options_;
};

TEST_F(TripletConfirmation, TrueWeakPairClosesItsTriangle) {
  const TriangleTest t = TestTriangle(0, 1, 2, pairs_[0], pairs_[1], pairs_[2]);
  EXPECT_LT(t.rotation_cycle_deg, 1e-9);
  EXPECT_LT(t.coplanarity_deg, 1e-6);
  EXPECT_EQ(t.closed_matches, 40);
  EXPECT_EQ(ConfirmWeakPairs(pairs_, options_), (std::vector<int64_t>{2, -2, -2}));
  // Either orientation of the stored pairs gives the same verdict.
  PairEstimate flipped = pairs_[2];
  flipped.image1 = 2;
  flipped.image2 = 1;
  flipped.R_21 = pairs_[2].R_21.transpose();
  flipped.t_21 = -flipped.R_21 * pairs_[2].t_21;
  for (auto& m : flipped.matches) std::swap(m.first, m.second);
  EXPECT_EQ(ConfirmWeakPairs({pairs_[0], pairs_[1], flipped}, options_), (std::vector<int64_t>{2, -2, -2}));
}

TEST_F(TripletConfirmation, WrongRotationIsNotConfirmed) {
  pairs_[0].R_21 = Eigen::AngleAxisd(47 * kDeg, Eigen::Vector3d(0.3, 1, 0).normalized()) * pairs_[0].R_21;
  EXPECT_NEAR(TestTriangle(0, 1, 2, pairs_[0], pairs_[1], pairs_[2]).rotation_cycle_deg, 47.0, 1e-6);
  EXPECT_EQ(ConfirmWeakPairs(pairs_, options_)[0], -1);
  // Within the cycle bound: a 2 degree error passes, 4 does not (bound 3).
  SetUp();
  const Eigen::Matrix3d truth = pairs_[0].R_21;
  pairs_[0].R_21 = Eigen::AngleAxisd(2 * kDeg, Eigen::Vector3d::UnitY()) * truth;
  EXPECT_EQ(ConfirmWeakPairs(pairs_, options_)[0], 2);
  pairs_[0].R_21 = Eigen::AngleAxisd(4 * kDeg, Eigen::Vector3d::UnitY()) * truth;
  EXPECT_EQ(ConfirmWeakPairs(pairs_, options_)[0], -1);
}

TEST_F(TripletConfirmation, BaselinesThatDoNotCloseAreNotConfirmed) {
  // Reversed baseline: the centres' directions are in one plane but the triangle does not close.
  pairs_[0].t_21 = -pairs_[0].t_21;
  EXPECT_EQ(TestTriangle(0, 1, 2, pairs_[0], pairs_[1], pairs_[2]).coplanarity_deg, 90.0);
  EXPECT_EQ(ConfirmWeakPairs(pairs_, options_)[0], -1);
  // Tilted 20 degrees out of the ring's plane (bound 5).
  SetUp();
  pairs_[0].t_21 = Eigen::AngleAxisd(20 * kDeg, pairs_[0].t_21.cross(Eigen::Vector3d::UnitY()).normalized()) *
                   pairs_[0].t_21;
  const double out = TestTriangle(0, 1, 2, pairs_[0], pairs_[1], pairs_[2]).coplanarity_deg;
  EXPECT_GT(out, 5.0);
  EXPECT_LT(out, 20.0 + 1e-9);
  EXPECT_EQ(ConfirmWeakPairs(pairs_, options_)[0], -1);
}

TEST_F(TripletConfirmation, MatchesMustTransferIntoTheThirdView) {
  // Only 4 of the weak pair's matches reach the same feature of image 2 (bound 5).
  for (size_t f = 4; f < pairs_[0].matches.size(); ++f) pairs_[0].matches[f].second += 100;
  EXPECT_EQ(TestTriangle(0, 1, 2, pairs_[0], pairs_[1], pairs_[2]).closed_matches, 4);
  EXPECT_EQ(ConfirmWeakPairs(pairs_, options_)[0], -1);
  options_.min_closed_matches = 4;
  EXPECT_EQ(ConfirmWeakPairs(pairs_, options_)[0], 2);
}

TEST_F(TripletConfirmation, AChainEndKeepsItsBestWeakPairAsALeaf) {
  // Image 1's only pair is weak and in no triangle: kept as its link to image 0 (which has a
  // verified pair), unless keep_leaf_pairs is off.
  EXPECT_EQ(ConfirmWeakPairs({pairs_[0], pairs_[1]}, options_), (std::vector<int64_t>{kLeafPair, -2}));
  options_.keep_leaf_pairs = false;
  EXPECT_EQ(ConfirmWeakPairs({pairs_[0], pairs_[1]}, options_), (std::vector<int64_t>{-1, -2}));
  options_.keep_leaf_pairs = true;
  // Two images joined by a weak pair alone, linked to nothing else: not kept.
  EXPECT_EQ(ConfirmWeakPairs({pairs_[0]}, options_), (std::vector<int64_t>{-1}));
  // Image 3 with two weak pairs to linked images whose triangle (with the verified 0 - 2)
  // does not close (one is 10 degrees off): the one with more inliers.
  PairEstimate to0 = TruePair(0, 3, views_[0], RingView(-23.5 * kDeg), 30);
  PairEstimate to2 = TruePair(2, 3, views_[2], RingView(-23.5 * kDeg), 45);
  to0.R_21 = Eigen::AngleAxisd(10 * kDeg, Eigen::Vector3d::UnitY()) * to0.R_21;
  to0.weak = to2.weak = true;
  EXPECT_EQ(ConfirmWeakPairs({pairs_[1], pairs_[2], to0, to2}, options_), (std::vector<int64_t>{-2, -2, -1, kLeafPair}));
}

TEST_F(TripletConfirmation, OnlyForWeaklyConnectedImages) {
  // Images 0 and 1 each with 3 verified pairs (to 2 and to two more images): their weak
  // pair is not tried although its triangle closes.
  std::vector<PairEstimate> pairs = pairs_;
  for (uint32_t other : {3u, 4u}) {
    const View v = RingView(other * 40.0 * kDeg);
    pairs.push_back(TruePair(0, other, views_[0], v, 40));
    pairs.push_back(TruePair(1, other, views_[1], v, 40));
  }
  EXPECT_EQ(ConfirmWeakPairs(pairs, options_)[0], -1);
  options_.max_verified_pairs = 3;
  EXPECT_EQ(ConfirmWeakPairs(pairs, options_)[0], 2);
}

TEST(TripletConfirmationOptions, CheckNamesTheKey) {
  TripletConfirmationOptions o;
  EXPECT_EQ(o.Check(), "");
  o.max_coplanarity_deg = 0;
  EXPECT_EQ(o.Check().rfind("max_coplanarity_deg", 0), 0u);
}

}  // namespace
}  // namespace pgba
