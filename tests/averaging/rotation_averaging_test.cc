#include "averaging/rotation_averaging.h"

#include <gtest/gtest.h>

#include "averaging/outlier_injection.h"
#include "pgba/geometry/rotation.h"
#include "relative_motion_fixture.h"

namespace pgba {
namespace {

using test::Layout;

struct Errors {
  double median = 0.0, max = 0.0;
};

Errors AverageAndCompare(const test::GroundTruth& gt, const test::RelativeMotions& m, const RotationAveragingOptions& options,
           RotationAveragingSummary* summary = nullptr) {
  std::map<uint32_t, Eigen::Matrix3d> rotations;
  EXPECT_TRUE(AverageRotations(CollectRelativeRotations(m.pairs, m.triplets, options.observations), options,
                               &rotations, summary));
  EXPECT_EQ(rotations.size(), gt.poses.size());
  const std::vector<double> err = test::RotationErrorsDeg(rotations, gt.poses);
  return {test::Median(err), test::Max(err)};
}

class RotationAveragingLayouts : public ::testing::TestWithParam<std::tuple<Layout, double>> {};

// Noise of RMS angle 0.1 - 0.5 deg on every relative rotation: median error < 0.1 deg,
// max < 0.5 deg on all three layouts.
TEST_P(RotationAveragingLayouts, AccurateUnderNoise) {
  const auto [layout, noise_deg] = GetParam();
  const test::GroundTruth gt = test::MakeLayout(layout, 7);
  test::NoiseModel noise;
  noise.rotation_deg = noise_deg;
  const test::RelativeMotions m = test::MakeRelativeMotions(gt, noise, 11);
  RotationAveragingSummary summary;
  const Errors e = AverageAndCompare(gt, m, RotationAveragingOptions(), &summary);
  std::cout << test::LayoutName(layout) << " noise " << noise_deg << " deg: " << m.pairs.size() << " pairs, "
            << m.triplets.size() << " triplets, error median " << e.median << " max " << e.max << " deg, "
            << summary.irls_iterations << " IRLS iterations\n";
  EXPECT_TRUE(summary.converged);
  EXPECT_LT(e.median, 0.1);
  EXPECT_LT(e.max, 0.5);
}

INSTANTIATE_TEST_SUITE_P(All, RotationAveragingLayouts,
                         ::testing::Combine(::testing::Values(Layout::kOrbit, Layout::kAerial, Layout::kVideo),
                                            ::testing::Values(0.1, 0.3, 0.5)));

class RotationAveragingOutliers : public ::testing::TestWithParam<std::tuple<Layout, double>> {};

// 10% and 20% of the pairs' and of the triplets' relative rotations replaced by random
// rotations: the median error stays < 0.5 deg.
TEST_P(RotationAveragingOutliers, RobustToRandomRotations) {
  const auto [layout, fraction] = GetParam();
  const test::GroundTruth gt = test::MakeLayout(layout, 3);
  test::NoiseModel noise;
  noise.rotation_deg = 0.3;
  test::RelativeMotions m = test::MakeRelativeMotions(gt, noise, 5);
  OutlierInjectionOptions inject;
  inject.fraction = fraction;
  inject.seed = 17;
  const OutlierInjectionResult injected = InjectRotationOutliers(inject, &m.pairs, &m.triplets);
  ASSERT_GT(injected.pairs.size(), 0u);
  ASSERT_GT(injected.triplets.size(), 0u);
  RotationAveragingSummary summary;
  const Errors e = AverageAndCompare(gt, m, RotationAveragingOptions(), &summary);
  std::cout << test::LayoutName(layout) << " outliers " << fraction << ": error median " << e.median << " max "
            << e.max << " deg, inliers " << summary.num_inliers << "/" << summary.num_observations << "\n";
  EXPECT_LT(e.median, 0.5);
}

INSTANTIATE_TEST_SUITE_P(All, RotationAveragingOutliers,
                         ::testing::Combine(::testing::Values(Layout::kOrbit, Layout::kAerial, Layout::kVideo),
                                            ::testing::Values(0.1, 0.2)));

// Stage 1 ranks validated observations first: corrupted pairs claiming far more inliers than
// anything else would otherwise form the spanning tree. The tree is then made of validated
// edges only, and the corrupted observations (exactly those) are excluded as outliers.
TEST(RotationAveraging, SpanningTreeIgnoresWellSupportedOutliers) {
  const test::GroundTruth gt = test::MakeLayout(Layout::kOrbit, 12);
  test::NoiseModel noise;
  noise.rotation_deg = 0.2;
  test::RelativeMotions m = test::MakeRelativeMotions(gt, noise, 13);
  OutlierInjectionOptions inject;
  inject.fraction = 0.3;
  inject.target = OutlierTarget::kPairs;
  const OutlierInjectionResult injected = InjectRotationOutliers(inject, &m.pairs, &m.triplets);
  for (int p : injected.pairs) m.pairs[p].num_inliers = 100000;
  RotationAveragingOptions options;
  options.max_l1_iterations = 0;  // the start alone must be in the basin of IRLS
  RotationAveragingSummary summary;
  const Errors e = AverageAndCompare(gt, m, options, &summary);
  EXPECT_EQ(summary.tree_validated, static_cast<int>(gt.poses.size()) - 1);
  EXPECT_EQ(summary.num_outliers, static_cast<int>(injected.pairs.size()));
  EXPECT_TRUE(summary.images_without_inliers.empty());
  EXPECT_LT(e.median, 0.1);
  EXPECT_LT(e.max, 0.5);
}

// Outliers are excluded as edges, not images: an image whose every observation is random
// still gets the rotation of the one it happens to fit (nothing tells which of its
// observations is right), its other observations are excluded, and no other image suffers.
// Without exclusion they are only counted.
TEST(RotationAveraging, OutliersExcludedAsEdges) {
  const test::GroundTruth gt = test::MakeLayout(Layout::kOrbit, 14);
  test::RelativeMotions m = test::MakeRelativeMotions(gt, test::NoiseModel(), 15);
  const uint32_t victim = 5;
  std::mt19937_64 rng(16);
  int corrupted = 0;
  for (TwoViewGeometry& p : m.pairs)
    if (p.image_id1 == victim || p.image_id2 == victim) {
      p.R_21 = RandomRotation(rng);
      ++corrupted;
    }
  for (LocalMotion& t : m.triplets)
    for (int k = 0; k < 3; ++k)
      if (t.image_ids[k] == victim) {
        t.local_poses[k] = Pose::FromRC(RandomRotation(rng), t.local_poses[k].C());
        corrupted += 2;
      }
  for (bool exclude : {true, false}) {
    RotationAveragingOptions options;
    options.exclude_outliers = exclude;
    RotationAveragingSummary summary;
    std::map<uint32_t, Eigen::Matrix3d> rotations;
    ASSERT_TRUE(AverageRotations(CollectRelativeRotations(m.pairs, m.triplets, options.observations), options,
                                 &rotations, &summary));
    EXPECT_EQ(rotations.size(), gt.poses.size());
    EXPECT_TRUE(summary.images_without_inliers.empty());
    EXPECT_GE(summary.num_outliers, corrupted - 2);  // the victim fits one pair or one triplet
    EXPECT_LE(summary.num_outliers, corrupted);
    rotations.erase(victim);
    std::map<uint32_t, Pose> others = gt.poses;
    others.erase(victim);
    const std::vector<double> err = test::RotationErrorsDeg(rotations, others);
    EXPECT_LT(test::Median(err), 0.1);
    EXPECT_LT(test::Max(err), 0.5);
  }
}

}  // namespace
}  // namespace pgba
