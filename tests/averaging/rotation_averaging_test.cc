#include "averaging/rotation_averaging.h"

#include <gtest/gtest.h>

#include "averaging/outlier_injection.h"
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

}  // namespace
}  // namespace pgba
