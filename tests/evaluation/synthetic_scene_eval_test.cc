// The evaluation on the project's synthetic scenes (modules/synthetic): the true poses give
// sigma at the analytic noise level, the outliers the generator planted as the missing
// inlier fraction, zero pose error, and the withheld loop of `longfocal` closing at the
// noise level.
#include <gtest/gtest.h>

#include <cmath>

#include "evaluation/evaluation.h"
#include "synthetic/synthetic_scene.h"
#include "tests/evaluation/test_scene.h"

namespace pgba {
namespace {

SyntheticScene Generate(SyntheticScenario scenario, double noise, double outliers, int num_points) {
  SyntheticOptions o;
  o.scenario = scenario;
  o.noise_px = noise;
  o.outlier_fraction = outliers;
  o.num_points = num_points;
  o.seed = 4;
  return GenerateSyntheticScene(o);
}

std::vector<int> TrackLengths(const Reconstruction& rec) {
  std::vector<int> n;
  for (const auto& [id, p] : rec.points3D) n.push_back(static_cast<int>(p.track.size()));
  return n;
}

TEST(SyntheticEvaluation, OrbitTruthAtNoiseLevel) {
  const double noise = 0.5;
  const SyntheticScene s = Generate(SyntheticScenario::kOrbit, noise, 0.0, 3000);
  // The input's poses are unknown (identity): evaluate the true poses on its tracks.
  const EvaluationMetrics m = Evaluate(s.gt, s.input, &s.gt, nullptr);
  EXPECT_EQ(m.images_input, s.input.images.size());
  EXPECT_EQ(m.images_registered, s.input.images.size());
  EXPECT_EQ(m.sigma.num_tracks, s.input.points3D.size());
  EXPECT_EQ(m.sigma.num_observations, s.input.NumObservations());
  const double expected = test::ExpectedSigmaRms(TrackLengths(s.input), noise);
  EXPECT_NEAR(m.sigma.rms / expected, 1.0, 0.03) << m.sigma.rms << " vs " << expected;
  EXPECT_GT(m.sigma.inlier_fraction, 0.999);
  ASSERT_TRUE(m.ground_truth && m.ground_truth->ok);
  EXPECT_LT(m.ground_truth->rot_err_deg_max, 1e-6);
  EXPECT_LT(m.ground_truth->center_err_rel_max, 1e-12);
}

TEST(SyntheticEvaluation, OrbitOutliersAreTheMissingInliers) {
  const double outliers = 0.03;
  const SyntheticScene s = Generate(SyntheticScenario::kOrbit, 0.5, outliers, 3000);
  const EvaluationMetrics m = Evaluate(s.gt, s.input, nullptr, nullptr);
  const double planted = static_cast<double>(s.outliers.size()) / s.input.NumObservations();
  // Each planted outlier (uniform in the image) is > 4 px off; a short track with an outlier
  // may drag a good observation out too, or fail, so the inlier fraction may be a little
  // lower than 1 - planted, never higher (beyond the rare outlier landing within 4 px).
  EXPECT_LT(m.sigma.inlier_fraction, 1.0 - planted + 0.002);
  EXPECT_GT(m.sigma.inlier_fraction, 1.0 - 2.0 * planted);
  // sigma_rms counts only observations under 4 px: still close to the noise level.
  const double expected = test::ExpectedSigmaRms(TrackLengths(s.input), 0.5);
  EXPECT_NEAR(m.sigma.rms / expected, 1.0, 0.08) << m.sigma.rms << " vs " << expected;
}

TEST(SyntheticEvaluation, LongFocalLoopClosesOnTruthAndNotWhenDrifted) {
  const double noise = 0.5;
  const SyntheticScene s = Generate(SyntheticScenario::kLongFocal, noise, 0.0, 2000);
  ASSERT_FALSE(s.loop_pairs.empty());
  const EvaluationMetrics m = Evaluate(s.gt, s.input, &s.gt, &s.loop_pairs);
  ASSERT_TRUE(m.loop && m.loop->Computable());
  EXPECT_EQ(m.loop->num_evaluated, s.loop_pairs.size());
  // Two views: E||r||^2 = sigma^2 per observation pair member -> RMS sigma / sqrt(2).
  EXPECT_NEAR(m.loop->rms / (noise / std::sqrt(2.0)), 1.0, 0.1) << m.loop->rms;

  // A drift of 0.002 deg (f = 156,000 px: ~5 px) at one end of the loop shows in the loop
  // error. About the camera's x axis: the ring's baselines are horizontal, so the image moves
  // across the epipolar lines (a shift along them would be absorbed by the point's depth).
  Reconstruction drifted = s.gt;
  const auto far_end = drifted.FindImageByName(s.loop_pairs.front().name_j);
  ASSERT_TRUE(far_end);
  Image& im = drifted.images.at(*far_end);
  im.pose = Pose::FromRC(ExpSO3(Eigen::Vector3d(0.002 * M_PI / 180.0, 0, 0)) * im.pose.R(), im.pose.C());
  const EvaluationMetrics d = Evaluate(drifted, s.input, &s.gt, &s.loop_pairs);
  EXPECT_GT(d.loop->rms, 3.0 * m.loop->rms) << d.loop->rms;
  EXPECT_NEAR(d.ground_truth->rot_err_deg_max, 0.002, 1e-4);
}

}  // namespace
}  // namespace pgba
