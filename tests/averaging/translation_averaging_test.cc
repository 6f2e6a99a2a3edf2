#include "averaging/translation_averaging.h"

#include <gtest/gtest.h>

#include "averaging/rotation_averaging.h"
#include "relative_motion_fixture.h"

namespace pgba {
namespace {

using test::Layout;

std::map<uint32_t, Eigen::Matrix3d> TrueRotations(const test::GroundTruth& gt) {
  std::map<uint32_t, Eigen::Matrix3d> R;
  for (const auto& [id, p] : gt.poses) R[id] = p.R();
  return R;
}

std::map<uint32_t, Eigen::Matrix3d> AveragedRotations(const test::RelativeMotions& m) {
  RotationAveragingOptions options;
  std::map<uint32_t, Eigen::Matrix3d> R;
  EXPECT_TRUE(AverageRotations(CollectRelativeRotations(m.pairs, m.triplets, options.observations), options, &R));
  return R;
}

// A single perfectly straight strip: every pairwise direction is the same vector, so the
// spacing of the cameras is invisible to direction-only methods; the triplets' scale makes it
// observable.
test::GroundTruth StraightStrip() {
  test::GroundTruth gt;
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> spacing(0.5, 1.5);
  double x = 0.0;
  for (uint32_t id = 1; id <= 20; ++id) {
    Eigen::Matrix3d R;
    R << 1, 0, 0, 0, -1, 0, 0, 0, -1;  // looking down
    gt.poses[id] = Pose::FromRC(R, Eigen::Vector3d(x, 0, 10));
    x += spacing(rng);  // irregular spacing: the truth is not a uniform grid
  }
  gt.extent = x;
  gt.pair_radius = 3.2;
  return gt;
}

// Without noise, and with the true rotations, the centres are recovered exactly up to a
// similarity, on every layout and on the straight strip.
TEST(TranslationAveraging, ExactWithoutNoise) {
  for (int k = 0; k < 4; ++k) {
    const test::GroundTruth gt = k < 3 ? test::MakeLayout(static_cast<Layout>(k), 2) : StraightStrip();
    test::NoiseModel noise;
    noise.rotation_deg = noise.direction_deg = noise.centre_rel = 0.0;
    const test::RelativeMotions m = test::MakeRelativeMotions(gt, noise, 3);
    std::map<uint32_t, Eigen::Vector3d> C;
    TranslationAveragingSummary summary;
    const auto R = TrueRotations(gt);
    ASSERT_TRUE(AverageTranslations(m.triplets, m.pairs, R, {}, &C, &summary)) << summary.message;
    ASSERT_EQ(C.size(), gt.poses.size());
    EXPECT_LT(test::Max(test::CentreErrorsRel(C, gt.poses, gt.extent, &R)), 1e-8) << "layout " << k;
    // Gauge: centroid at the origin.
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (const auto& [id, c] : C) centroid += c / C.size();
    EXPECT_LT(centroid.norm(), 1e-9);
  }
}

class TranslationAveragingLayouts : public ::testing::TestWithParam<std::tuple<int, bool>> {};

// Noisy relative motions (0.3 deg rotations and directions, 0.3% triplet centre noise),
// rotations from rotation averaging: median centre error < 1% of the extent after Sim(3)
// alignment, with and without the nonlinear refinement, including the collinear strip.
TEST_P(TranslationAveragingLayouts, AccurateUnderNoise) {
  const auto [layout, refine] = GetParam();
  const test::GroundTruth gt = layout < 3 ? test::MakeLayout(static_cast<Layout>(layout), 4) : StraightStrip();
  const test::RelativeMotions m = test::MakeRelativeMotions(gt, test::NoiseModel(), 9);
  TranslationAveragingOptions options;
  options.refine = refine;
  std::map<uint32_t, Eigen::Vector3d> C;
  TranslationAveragingSummary summary;
  const auto R = AveragedRotations(m);
  ASSERT_TRUE(AverageTranslations(m.triplets, m.pairs, R, options, &C, &summary));
  const std::vector<double> err = test::CentreErrorsRel(C, gt.poses, gt.extent, &R);
  std::cout << (layout < 3 ? test::LayoutName(static_cast<Layout>(layout)) : "strip") << (refine ? " refined" : " linear")
            << ": centre error median " << test::Median(err) << " max " << test::Max(err) << " of extent, "
            << summary.scale_links << " scale links, " << summary.refine_iterations << " refine iterations, "
            << summary.seconds << " s\n";
  EXPECT_LT(test::Median(err), 0.01);
  EXPECT_LT(test::Max(err), 0.03);
}

INSTANTIATE_TEST_SUITE_P(All, TranslationAveragingLayouts,
                         ::testing::Combine(::testing::Values(0, 1, 2, 3), ::testing::Bool()));

// Triplets whose local centres are garbage (10% of them, one view moved by a triplet size)
// are absorbed by the robust losses.
TEST(TranslationAveraging, RobustToCorruptedTriplets) {
  const test::GroundTruth gt = test::MakeLayout(Layout::kAerial, 6);
  test::RelativeMotions m = test::MakeRelativeMotions(gt, test::NoiseModel(), 2);
  std::mt19937_64 rng(8);
  for (size_t t = 0; t < m.triplets.size(); t += 10) {
    Pose& p = m.triplets[t].local_poses[t % 3];
    const double size = (m.triplets[t].local_poses[0].C() - m.triplets[t].local_poses[1].C()).norm();
    p = Pose::FromRC(p.R(), p.C() + size * RandomRotation(rng).col(0));
  }
  std::map<uint32_t, Eigen::Vector3d> C;
  TranslationAveragingSummary summary;
  ASSERT_TRUE(AverageTranslations(m.triplets, m.pairs, AveragedRotations(m), {}, &C, &summary));
  const std::vector<double> err = test::CentreErrorsRel(C, gt.poses, gt.extent);
  std::cout << "aerial with 10% corrupted triplets: median " << test::Median(err) << " max " << test::Max(err)
            << "; " << summary.scale_iterations << " scale, " << summary.centre_iterations << " centre, "
            << summary.refine_iterations << " refine iterations, " << summary.seconds << " s\n";
  EXPECT_LT(test::Median(err), 0.01);
}

// Triplets touching in one image only do not fix their relative scale: refused.
TEST(TranslationAveraging, RefusesTripletsNotSharingPairs) {
  const test::GroundTruth gt = StraightStrip();
  test::NoiseModel noise;
  test::RelativeMotions m = test::MakeRelativeMotions(gt, noise, 1);
  std::vector<LocalMotion> chain;  // (1,2,3), (3,4,5): share image 3 only
  for (const LocalMotion& t : m.triplets)
    if ((t.image_ids == std::vector<uint32_t>{1, 2, 3}) || (t.image_ids == std::vector<uint32_t>{3, 4, 5}))
      chain.push_back(t);
  ASSERT_EQ(chain.size(), 2u);
  std::map<uint32_t, Eigen::Vector3d> C;
  TranslationAveragingSummary summary;
  EXPECT_FALSE(AverageTranslations(chain, {}, TrueRotations(gt), {}, &C, &summary));
  EXPECT_TRUE(C.empty());
  EXPECT_FALSE(summary.message.empty());
}

TEST(TranslationAveraging, Deterministic) {
  const test::GroundTruth gt = test::MakeLayout(Layout::kOrbit, 1);
  const test::RelativeMotions m = test::MakeRelativeMotions(gt, test::NoiseModel(), 1);
  const auto R = AveragedRotations(m);
  std::map<uint32_t, Eigen::Vector3d> a, b;
  ASSERT_TRUE(AverageTranslations(m.triplets, m.pairs, R, {}, &a));
  ASSERT_TRUE(AverageTranslations(m.triplets, m.pairs, R, {}, &b));
  for (const auto& [id, c] : a) EXPECT_EQ(c, b.at(id));
}

}  // namespace
}  // namespace pgba
