// The view graph (EstimatePairs) with and without the image front end's verified geometries,
// on a synthetic orbit (70 views, 0.5 px noise, 2% outlier observations) whose true relative poses are
// the reference: the front end's poses are the truth disturbed by 0.1 deg (rotation) and
// 1 deg (translation direction), the size of a front-end error, a disturbance the refinement must remove and the straight
// reuse must keep.
#include "triplets/pair_estimation.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <random>

#include "pgba/geometry/rotation.h"
#include "tests/support/acceptance_scene.h"

namespace pgba {
namespace {

const SyntheticScene& Scene() {
  static const SyntheticScene scene = test::AcceptanceScene(SyntheticScenario::kOrbit, 0, 3);
  return scene;
}

TwoViewGeometry TrueGeometry(uint32_t id1, uint32_t id2) {
  const Pose& a = Scene().gt.images.at(id1).pose;
  const Pose& b = Scene().gt.images.at(id2).pose;
  TwoViewGeometry g;
  g.image_id1 = id1;
  g.image_id2 = id2;
  g.R_21 = b.R() * a.R().transpose();
  g.t_21 = (b.t() - g.R_21 * a.t()).normalized();
  return g;
}

double RotationErrorDeg(const TwoViewGeometry& g) { return RotationAngleDeg(g.R_21, TrueGeometry(g.image_id1, g.image_id2).R_21); }

// The `q` quantile of the pairs' relative rotation errors against the truth, degrees.
double RotationErrorQuantileDeg(const std::vector<TwoViewGeometry>& pairs, double q) {
  std::vector<double> e;
  for (const TwoViewGeometry& g : pairs) e.push_back(RotationErrorDeg(g));
  std::sort(e.begin(), e.end());
  return e.empty() ? 1e9 : e[static_cast<size_t>(q * (e.size() - 1))];
}

// The front end's geometry of every pair of `pairs`: the truth, disturbed, with the
// estimated pair's inlier count and triangulation angle.
std::vector<TwoViewGeometry> FrontEnd(const std::vector<TwoViewGeometry>& pairs) {
  std::mt19937_64 rng(11);
  std::vector<TwoViewGeometry> out;
  for (const TwoViewGeometry& p : pairs) {
    TwoViewGeometry g = TrueGeometry(p.image_id1, p.image_id2);
    g.R_21 = RandomRotationOfAngle(rng, 0.1 * M_PI / 180.0) * g.R_21;
    g.t_21 = RandomRotationOfAngle(rng, 1.0 * M_PI / 180.0) * g.t_21;
    g.num_inliers = p.num_inliers;
    g.num_tracks = p.num_tracks;
    g.median_triangulation_angle_deg = p.median_triangulation_angle_deg;
    out.push_back(g);
  }
  return out;
}

PairOptions WithFrontEnd(const std::string& mode, bool track_only_pairs = true) {
  PairOptions o;
  o.front_end = mode;
  o.track_only_pairs = track_only_pairs;
  return o;
}

TEST(ViewGraph, RefineFromTheFrontEndPoseNeedsNoRansacAndKeepsTheAccuracy) {
  PairStats est_stats, ref_stats;
  const auto estimated = EstimatePairs(Scene().input, PairOptions{}, &est_stats);
  ASSERT_GE(estimated.size(), 20u);
  const auto front_end = FrontEnd(estimated);
  const auto refined = EstimatePairs(Scene().input, WithFrontEnd("refine"), &ref_stats, &front_end);
  EXPECT_EQ(ref_stats.pairs_front_end, static_cast<int>(estimated.size()));
  EXPECT_EQ(ref_stats.pairs_refined, static_cast<int>(estimated.size()));
  // RANSAC runs for the candidates it had rejected, and for the pairs whose refinement lost
  // its consensus from the disturbed start (measured: 1 of 387).
  EXPECT_LE(ref_stats.pairs_refine_fallback, 2);
  EXPECT_EQ(ref_stats.pairs_ransac,
            est_stats.pairs_estimated - static_cast<int>(estimated.size()) + ref_stats.pairs_refine_fallback);
  EXPECT_EQ(est_stats.pairs_ransac, est_stats.pairs_estimated);
  ASSERT_EQ(refined.size(), estimated.size());
  double total_refined = 0, total_estimated = 0;
  for (size_t i = 0; i < refined.size(); ++i) {
    EXPECT_EQ(refined[i].image_id1, estimated[i].image_id1);
    EXPECT_EQ(refined[i].image_id2, estimated[i].image_id2);
    // A weak pair's inliers move with its pose along the flat direction (measured: up to 22%).
    EXPECT_NEAR(refined[i].num_inliers, estimated[i].num_inliers, 0.25 * estimated[i].num_inliers + 1) << i;
    total_refined += refined[i].num_inliers;
    total_estimated += estimated[i].num_inliers;
  }
  EXPECT_NEAR(total_refined, total_estimated, 0.005 * total_estimated);
  // Against the truth: the 0.1 deg of the start are gone, the errors are RANSAC's (measured:
  // median 0.0780 vs 0.0771 deg, 90th percentile 0.211 vs 0.205 deg, with one refinement pass).
  for (double q : {0.5, 0.9}) {
    const double est = RotationErrorQuantileDeg(estimated, q), ref = RotationErrorQuantileDeg(refined, q);
    std::cout << "relative rotation error, quantile " << q << ": RANSAC " << est << " deg, refined from the front end "
              << ref << " deg" << std::endl;
    EXPECT_LT(est, 0.25);
    EXPECT_LE(ref, 1.05 * est) << q;
  }
}

TEST(ViewGraph, ReuseTakesTheFrontEndGeometryAsIs) {
  const auto estimated = EstimatePairs(Scene().input, PairOptions{});
  const auto front_end = FrontEnd(estimated);
  PairStats stats;
  const auto reused = EstimatePairs(Scene().input, WithFrontEnd("reuse"), &stats, &front_end);
  EXPECT_EQ(stats.pairs_reused, static_cast<int>(front_end.size()));
  ASSERT_EQ(reused.size(), front_end.size());
  for (size_t i = 0; i < reused.size(); ++i) {
    EXPECT_TRUE(reused[i].R_21.isApprox(front_end[i].R_21, 1e-15));
    EXPECT_NEAR(RotationErrorDeg(reused[i]), 0.1, 1e-6);  // the disturbance is kept
  }
  // "estimate" ignores the front end: the result is the tracks-only one.
  PairStats est_stats;
  const auto ignored = EstimatePairs(Scene().input, WithFrontEnd("estimate"), &est_stats, &front_end);
  EXPECT_EQ(est_stats.pairs_front_end, 0);
  ASSERT_EQ(ignored.size(), estimated.size());
  for (size_t i = 0; i < ignored.size(); ++i) EXPECT_EQ(ignored[i].R_21, estimated[i].R_21);
}

TEST(ViewGraph, AFrontEndPoseTheTracksContradictFallsBackToRansac) {
  const auto estimated = EstimatePairs(Scene().input, PairOptions{});
  auto front_end = FrontEnd(estimated);
  PairStats before, stats;
  EstimatePairs(Scene().input, WithFrontEnd("refine"), &before, &front_end);
  std::mt19937_64 rng(5);
  front_end[0].R_21 = RandomRotationOfAngle(rng, M_PI / 2) * front_end[0].R_21;  // 90 degrees off
  const auto refined = EstimatePairs(Scene().input, WithFrontEnd("refine"), &stats, &front_end);
  EXPECT_EQ(stats.pairs_refine_fallback, before.pairs_refine_fallback + 1);
  ASSERT_EQ(refined.size(), estimated.size());
  EXPECT_LT(RotationErrorDeg(refined[0]), 0.05);
}

TEST(ViewGraph, EitherOrientationOfAFrontEndPairGivesTheSameResult) {
  const auto estimated = EstimatePairs(Scene().input, PairOptions{});
  const auto front_end = FrontEnd(estimated);
  std::vector<TwoViewGeometry> flipped = front_end;
  for (TwoViewGeometry& g : flipped) {  // x_1 = R_21^T x_2 - R_21^T t_21
    std::swap(g.image_id1, g.image_id2);
    g.t_21 = -(g.R_21.transpose() * g.t_21);
    g.R_21 = g.R_21.transpose().eval();
  }
  const auto a = EstimatePairs(Scene().input, WithFrontEnd("reuse"), nullptr, &front_end);
  const auto b = EstimatePairs(Scene().input, WithFrontEnd("reuse"), nullptr, &flipped);
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].image_id1, b[i].image_id1);
    EXPECT_TRUE(a[i].R_21.isApprox(b[i].R_21, 1e-12));
    EXPECT_TRUE(a[i].t_21.isApprox(b[i].t_21, 1e-12));
  }
}

TEST(ViewGraph, TrackOnlyPairsAreEstimatedOnlyWhenAsked) {
  const auto estimated = EstimatePairs(Scene().input, PairOptions{});
  auto front_end = FrontEnd(estimated);
  front_end.resize(front_end.size() / 2);  // the front end verified half of them
  PairStats with, without;
  const auto all = EstimatePairs(Scene().input, WithFrontEnd("refine", true), &with, &front_end);
  const auto only = EstimatePairs(Scene().input, WithFrontEnd("refine", false), &without, &front_end);
  EXPECT_EQ(all.size(), estimated.size());
  EXPECT_EQ(only.size(), front_end.size());
  EXPECT_EQ(without.pairs_ransac, 0);
  EXPECT_EQ(without.pairs_estimated, static_cast<int>(front_end.size()));
  EXPECT_EQ(without.pairs_track_only_skipped, with.pairs_estimated - static_cast<int>(front_end.size()));
  for (size_t i = 0; i < only.size(); ++i) EXPECT_EQ(only[i].image_id2, front_end[i].image_id2);
}

TEST(ViewGraph, SameResultOnOneAndTwoThreads) {
  const auto front_end = FrontEnd(EstimatePairs(Scene().input, PairOptions{}));
  std::vector<TwoViewGeometry> runs[2];
  for (int threads : {1, 2}) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    runs[threads - 1] = EstimatePairs(Scene().input, WithFrontEnd("refine"), nullptr, &front_end);
  }
  ASSERT_EQ(runs[0].size(), runs[1].size());
  for (size_t i = 0; i < runs[0].size(); ++i) {
    EXPECT_EQ(runs[0][i].R_21, runs[1][i].R_21);
    EXPECT_EQ(runs[0][i].t_21, runs[1][i].t_21);
    EXPECT_EQ(runs[0][i].num_inliers, runs[1][i].num_inliers);
  }
}

TEST(ViewGraph, UnknownFrontEndModeIsRejected) {
  EXPECT_EQ(PairOptions{}.Check(), "");
  EXPECT_NE(WithFrontEnd("ransac").Check().find("front_end must be one of"), std::string::npos);
  EXPECT_THROW(EstimatePairs(Scene().input, WithFrontEnd("ransac")), std::invalid_argument);
}

}  // namespace
}  // namespace pgba
