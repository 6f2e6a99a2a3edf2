// Loop-closure error: at the noise level on the truth, growing with a perturbed end.
#include <gtest/gtest.h>

#include <cmath>

#include "evaluation/loop_closure.h"
#include "tests/evaluation/test_scene.h"

namespace pgba {
namespace {

TEST(LoopClosure, NoiseLevelOnTruth) {
  const double noise = 0.5;
  const test::TestScene s = test::MakeTestScene(31, 12, 50, noise, 2000);
  const LoopClosureResult r = EvaluateLoopClosure(s.gt, s.loops);
  EXPECT_EQ(r.num_correspondences, 2000u);
  EXPECT_EQ(r.num_evaluated, 2000u);
  EXPECT_EQ(r.num_failed, 0u);
  // Two views, 4 residuals, 3 unknowns: E[sum ||r||^2] = sigma^2 per correspondence, i.e.
  // an RMS of sigma / sqrt(2) per observation (2000 dof: ~1.6% standard error).
  EXPECT_NEAR(r.rms / (noise / std::sqrt(2.0)), 1.0, 0.06) << r.rms;
  EXPECT_LT(r.median, r.rms * 1.2);
}

TEST(LoopClosure, GrowsWhenOneEndIsPerturbed) {
  const test::TestScene s = test::MakeTestScene(32, 12, 50, 0.5, 1000);
  const double base = EvaluateLoopClosure(s.gt, s.loops).rms;
  double previous = base;
  for (double deg : {0.2, 0.5, 1.0}) {
    Reconstruction model = s.gt;
    Image& far_end = model.images.at(7);  // image 6: the loop's second image
    ASSERT_EQ(far_end.name, s.loops[0].name_j);
    std::mt19937_64 rng(1);
    far_end.pose = Pose::FromRC(RandomRotationOfAngle(rng, deg * M_PI / 180.0) * far_end.pose.R(), far_end.pose.C());
    const LoopClosureResult r = EvaluateLoopClosure(model, s.loops);
    EXPECT_GT(r.rms, previous * 1.2) << deg << ": " << r.rms;
    previous = r.rms;
  }
  EXPECT_GT(previous, 5.0 * base);
}

TEST(LoopClosure, UnregisteredImagesAreSkipped) {
  const test::TestScene s = test::MakeTestScene(33, 12, 50, 0.5, 100);
  Reconstruction model = test::RenumberedPosesOnly(s.gt, 40);  // ids differ, names match
  const LoopClosureResult all = EvaluateLoopClosure(model, s.loops);
  EXPECT_EQ(all.num_evaluated, 100u);
  model.images.erase(41);  // image 0, the loop's first image
  const LoopClosureResult none = EvaluateLoopClosure(model, s.loops);
  EXPECT_EQ(none.num_unregistered, 100u);
  EXPECT_EQ(none.num_evaluated, 0u);
  EXPECT_FALSE(none.Computable());
}

}  // namespace
}  // namespace pgba
