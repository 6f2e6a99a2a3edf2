// Pose errors against ground truth: exact zero on the truth and on any similar copy of it,
// and exactly the rotations / displacements a model was given.
#include <gtest/gtest.h>

#include <algorithm>

#include "evaluation/ground_truth.h"
#include "evaluation/statistics.h"
#include "tests/evaluation/test_scene.h"

namespace pgba {
namespace {

Sim3 SomeSim3(uint64_t seed) {
  std::mt19937_64 rng(seed);
  Sim3 s;
  s.s = 0.37;
  s.R = RandomRotation(rng);
  s.t = Eigen::Vector3d(12.0, -4.0, 250.0);
  return s;
}

// Brute-force largest distance between the true centres: the definition of the extent.
double Diameter(const Reconstruction& rec) {
  double d = 0.0;
  for (const auto& [i, a] : rec.images)
    for (const auto& [j, b] : rec.images) d = std::max(d, (a.pose.C() - b.pose.C()).norm());
  return d;
}

TEST(GroundTruth, TruthHasZeroError) {
  const test::TestScene s = test::MakeTestScene(21, 12, 100);
  const GroundTruthErrors e = CompareToGroundTruth(s.gt, s.gt);
  ASSERT_TRUE(e.ok);
  EXPECT_EQ(e.num_common, 12u);
  EXPECT_EQ(e.num_alignment_inliers, 12u);
  EXPECT_NEAR(e.scene_extent, Diameter(s.gt), 1e-12);
  EXPECT_LT(e.rot_err_deg_max, 1e-6);
  EXPECT_LT(e.center_err_rel_max, 1e-12);
}

TEST(GroundTruth, SimilarCopyHasZeroError) {
  const test::TestScene s = test::MakeTestScene(22, 12, 100);
  const Sim3 S = SomeSim3(1);
  Reconstruction model = test::RenumberedPosesOnly(s.gt, 50);
  for (auto& [id, im] : model.images) im.pose = S.Apply(im.pose);
  const GroundTruthErrors e = CompareToGroundTruth(model, s.gt);
  ASSERT_TRUE(e.ok);
  EXPECT_LT(e.rot_err_deg_max, 1e-6);
  EXPECT_LT(e.center_err_rel_max, 1e-12);
  // The alignment is the inverse similarity.
  EXPECT_NEAR(e.alignment.s * S.s, 1.0, 1e-12);
  EXPECT_LT(RotationAngleDeg(e.alignment.R * S.R, Eigen::Matrix3d::Identity()), 1e-9);
}

// The gauge-free relative errors: zero under any similarity of the whole model (no alignment
// involved), and exactly the known angle for the pairs of one rotated camera.
TEST(GroundTruth, RelativeErrorsAreGaugeFreeAndExact) {
  const test::TestScene s = test::MakeTestScene(24, 12, 100);
  const Sim3 S = SomeSim3(2);
  Reconstruction model = test::RenumberedPosesOnly(s.gt, 50);
  for (auto& [id, im] : model.images) im.pose = S.Apply(im.pose);
  GroundTruthErrors e = CompareToGroundTruth(model, s.gt);
  EXPECT_EQ(e.num_pairs, 66u);
  EXPECT_LT(e.rel_rot_err_deg_max, 1e-6);
  EXPECT_LT(e.rel_dir_err_deg_max, 1e-6);
  // One camera rotated by 1.5 deg about a random axis: the 11 of the 66
  // pairs see exactly 1.5 deg, the others 0 (median 0); the direction from that camera to
  // each other centre turns by at most 1.5 deg.
  std::mt19937_64 rng(9);
  Image& first = model.images.begin()->second;
  first.pose = Pose::FromRC(first.pose.R() * RandomRotationOfAngle(rng, 1.5 * M_PI / 180.0), first.pose.C());
  e = CompareToGroundTruth(model, s.gt);
  EXPECT_NEAR(e.rel_rot_err_deg_max, 1.5, 1e-9);
  EXPECT_LT(e.rel_rot_err_deg_median, 1e-6);
  EXPECT_LE(e.rel_dir_err_deg_max, 1.5 + 1e-9);
  EXPECT_GT(e.rel_dir_err_deg_max, 0.1);
}

TEST(GroundTruth, ReportsKnownRotationErrors) {
  const test::TestScene s = test::MakeTestScene(23, 12, 100);
  std::mt19937_64 rng(5);
  // 7 of 12 images rotated by known angles about random axes (centres untouched, so the
  // alignment stays exact), then the whole model moved by a similarity.
  const std::map<std::string, double> angles_deg = {{test::ImageName(0), 0.5}, {test::ImageName(2), 0.1},
                                                    {test::ImageName(3), 0.25}, {test::ImageName(5), 1.5},
                                                    {test::ImageName(7), 0.05}, {test::ImageName(8), 0.7},
                                                    {test::ImageName(11), 0.3}};
  const Sim3 S = SomeSim3(2);
  Reconstruction model = test::RenumberedPosesOnly(s.gt, 0);
  for (auto& [id, im] : model.images) {
    auto it = angles_deg.find(im.name);
    if (it != angles_deg.end())
      im.pose = Pose::FromRC(RandomRotationOfAngle(rng, it->second * M_PI / 180.0) * im.pose.R(), im.pose.C());
    im.pose = S.Apply(im.pose);
  }
  const GroundTruthErrors e = CompareToGroundTruth(model, s.gt);
  ASSERT_TRUE(e.ok);
  std::vector<double> expected;
  for (size_t i = 0; i < e.names.size(); ++i) {
    auto it = angles_deg.find(e.names[i]);
    const double want = it == angles_deg.end() ? 0.0 : it->second;
    expected.push_back(want);
    EXPECT_NEAR(e.rot_err_deg[i], want, 1e-7) << e.names[i];
  }
  // 12 values, 5 zeros: the median is the mean of the 6th and 7th smallest, (0.05+0.1)/2.
  EXPECT_NEAR(e.rot_err_deg_median, 0.075, 1e-7);
  EXPECT_NEAR(e.rot_err_deg_max, 1.5, 1e-7);
  EXPECT_LT(e.center_err_rel_max, 1e-12);
}

TEST(GroundTruth, ReportsKnownCentreDisplacementsRobustly) {
  const test::TestScene s = test::MakeTestScene(24, 12, 100);
  const double extent = Diameter(s.gt);
  // Two cameras displaced by 3% and 8% of the extent. A plain least-squares alignment would
  // tilt towards them and smear their error over all images; the robust one leaves the other
  // ten exact.
  const std::map<std::string, Eigen::Vector3d> shifts = {
      {test::ImageName(4), 0.03 * extent * Eigen::Vector3d(0.6, 0.0, 0.8)},
      {test::ImageName(9), 0.08 * extent * Eigen::Vector3d(0.0, -1.0, 0.0)}};
  const Sim3 S = SomeSim3(3);
  Reconstruction model = test::RenumberedPosesOnly(s.gt, 7);
  for (auto& [id, im] : model.images) {
    auto it = shifts.find(im.name);
    if (it != shifts.end()) im.pose = Pose::FromRC(im.pose.R(), im.pose.C() + it->second);
    im.pose = S.Apply(im.pose);
  }
  const GroundTruthErrors e = CompareToGroundTruth(model, s.gt);
  ASSERT_TRUE(e.ok);
  EXPECT_EQ(e.num_alignment_inliers, 10u);
  for (size_t i = 0; i < e.names.size(); ++i) {
    auto it = shifts.find(e.names[i]);
    const double want = it == shifts.end() ? 0.0 : it->second.norm() / extent;
    EXPECT_NEAR(e.center_err_rel[i], want, 1e-10) << e.names[i];
    EXPECT_LT(e.rot_err_deg[i], 1e-6) << e.names[i];
  }
  EXPECT_NEAR(e.center_err_rel_max, 0.08, 1e-10);
  EXPECT_LT(e.center_err_rel_median, 1e-10);

  // Without the re-alignment rounds the two outliers pull the similarity: every image errs.
  GroundTruthOptions plain;
  plain.max_rounds = 0;
  const GroundTruthErrors p = CompareToGroundTruth(model, s.gt, plain);
  EXPECT_GT(p.center_err_rel_median, 1e-4);
}

TEST(GroundTruth, OnlyCommonImagesAndDegenerateCases) {
  const test::TestScene s = test::MakeTestScene(25, 12, 100);
  Reconstruction model = test::RenumberedPosesOnly(s.gt, 0);
  model.images.erase(3);
  model.images.erase(4);
  Image extra = model.images.at(1);
  extra.image_id = 99;
  extra.name = "not_in_gt.jpg";
  model.images[99] = extra;
  const GroundTruthErrors e = CompareToGroundTruth(model, s.gt);
  ASSERT_TRUE(e.ok);
  EXPECT_EQ(e.num_common, 10u);
  EXPECT_EQ(e.names.size(), 10u);
  EXPECT_NEAR(e.scene_extent, Diameter(s.gt), 1e-12);  // extent of the whole GT

  Reconstruction two = test::RenumberedPosesOnly(s.gt, 0);
  for (uint32_t id = 3; id <= 12; ++id) two.images.erase(id);
  EXPECT_FALSE(CompareToGroundTruth(two, s.gt).ok);
}

TEST(Statistics, MedianRmsMax) {
  EXPECT_DOUBLE_EQ(Median({3.0, 1.0, 2.0}), 2.0);
  EXPECT_DOUBLE_EQ(Median({4.0, 1.0, 3.0, 2.0}), 2.5);
  EXPECT_TRUE(std::isnan(Median({})));
  EXPECT_DOUBLE_EQ(Rms({3.0, 4.0}), std::sqrt(12.5));
  EXPECT_DOUBLE_EQ(Max({3.0, -4.0}), 3.0);
}

}  // namespace
}  // namespace pgba
