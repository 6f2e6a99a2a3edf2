// sigma against its analytic expectation, determinism, and name matching.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <random>

#include "evaluation/sigma.h"
#include "pgba/scene/triangulate_model.h"
#include "tests/evaluation/test_scene.h"

namespace pgba {
namespace {

std::vector<int> TrackLengths(const Reconstruction& obs, const PoseMap& poses) {
  std::vector<int> lengths;
  for (const auto& [id, p] : obs.points3D) {
    int n = 0;
    for (const auto& el : p.track) n += poses.count(el.image_id) > 0;
    if (n >= 2) lengths.push_back(n);
  }
  return lengths;
}

TEST(Sigma, TruePosesGiveTheNoiseLevel) {
  for (double noise : {0.3, 1.0}) {
    const test::TestScene s = test::MakeTestScene(7, 12, 3000, noise);
    const RegisteredViews views = MatchImagesByName(s.gt, s.gt);
    const SigmaResult r = EvaluateSigma(s.gt, views.poses);
    const std::vector<int> lengths = TrackLengths(s.gt, views.poses);
    const double expected = test::ExpectedSigmaRms(lengths, noise);
    size_t num_obs = 0;
    for (int n : lengths) num_obs += n;
    EXPECT_EQ(r.num_tracks, s.gt.points3D.size());
    EXPECT_EQ(r.num_triangulated, r.num_tracks);
    EXPECT_EQ(r.num_observations, num_obs);
    // ~20k observations: the RMS of the sample is within ~0.5% of its expectation (1 sigma).
    EXPECT_NEAR(r.rms / expected, 1.0, 0.03) << "noise " << noise << " rms " << r.rms << " expected " << expected;
    // 4 px is > 4 noise sigmas for both levels: essentially every observation is an inlier.
    EXPECT_GT(r.inlier_fraction, 0.999);
    EXPECT_LE(r.inlier_fraction, 1.0);
  }
}

// The tracks sigma counts as triangulated are the points TriangulateModel keeps for the same
// poses: one number for the console's points, the evaluation table and report.json. Short
// tracks, noise of 2 px, 10% of the observations moved 3-15 px and poses a little off put many
// tracks near the 4 px threshold, where a triangulation that stops after fewer iterations keeps
// tracks the model does not (10 iterations: 36 more of 3342).
TEST(Sigma, TracksTriangulatedAreTheModelsPoints) {
  test::TestScene s = test::MakeTestScene(11, 12, 4000, 2.0, 0, 0.25);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (auto& [id, im] : s.gt.images)
    for (Point2D& p : im.points2D)
      if (unit(rng) < 0.1) {
        const double a = 2.0 * M_PI * unit(rng);
        p.xy += (3.0 + 12.0 * unit(rng)) * Eigen::Vector2d(std::cos(a), std::sin(a));
      }
  PoseMap poses;
  for (const auto& [id, im] : s.gt.images)
    poses.emplace(id, Pose::FromQt(im.pose.q(), im.pose.t() + 0.002 * Eigen::Vector3d(unit(rng) - 0.5, unit(rng) - 0.5,
                                                                                      unit(rng) - 0.5)));
  const SigmaResult r = EvaluateSigma(s.gt, poses);
  const Reconstruction model = TriangulateModel(s.gt, poses);
  EXPECT_LT(r.num_triangulated, r.num_tracks);  // the outliers cost some tracks
  EXPECT_EQ(r.num_triangulated, model.points3D.size());
}

TEST(Sigma, MedianOfLongTracks) {
  // Every point in all 12 views: each residual is close to an isotropic 2D Gaussian with
  // per-axis variance sigma^2 (1 - 3/(2n)), so its norm is ~Rayleigh with median
  // sigma sqrt(1 - 3/(2n)) sqrt(2 ln 2). (Short tracks are not: a 2-view residual lies along
  // the epipolar direction, a half-normal with a smaller median.)
  const double noise = 0.5;
  const test::TestScene s = test::MakeTestScene(17, 12, 3000, noise, 0, 1.0);
  const SigmaResult r = EvaluateSigma(s.gt, MatchImagesByName(s.gt, s.gt).poses);
  ASSERT_EQ(r.num_observations, 12u * s.gt.points3D.size());
  const double expected = noise * std::sqrt(1.0 - 3.0 / 24.0) * std::sqrt(2.0 * std::log(2.0));
  EXPECT_NEAR(r.median / expected, 1.0, 0.03) << r.median << " vs " << expected;
  EXPECT_NEAR(r.rms / test::ExpectedSigmaRms({12}, noise), 1.0, 0.02);
}

TEST(Sigma, InlierThresholdCutsTheRms) {
  const test::TestScene s = test::MakeTestScene(8, 12, 1500, 1.0);
  const RegisteredViews views = MatchImagesByName(s.gt, s.gt);
  SigmaOptions opt;
  opt.inlier_px = 1.0;
  const SigmaResult r = EvaluateSigma(s.gt, views.poses, opt);
  // Residual norms are ~Rayleigh with scale ~0.8 px: a large share exceeds 1 px.
  EXPECT_LT(r.inlier_fraction, 0.75);
  EXPECT_GT(r.inlier_fraction, 0.35);
  EXPECT_LT(r.rms, 1.0);
  EXPECT_EQ(r.num_inliers, static_cast<size_t>(std::llround(r.inlier_fraction * r.num_observations)));
}

TEST(Sigma, DeterministicUnderParallelism) {
  const test::TestScene s = test::MakeTestScene(9, 12, 3000, 0.5);
  const RegisteredViews views = MatchImagesByName(s.gt, s.gt);
  // Perturb poses so that tracks need several Gauss-Newton iterations.
  PoseMap poses = views.poses;
  std::mt19937_64 rng(3);
  for (auto& [id, p] : poses) p = Pose::FromRC(RandomRotationOfAngle(rng, 0.002) * p.R(), p.C());
  const SigmaResult a = EvaluateSigma(s.gt, poses);
  const SigmaResult b = EvaluateSigma(s.gt, poses);
  SigmaResult serial;
  {
    tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
    serial = EvaluateSigma(s.gt, poses);
  }
  for (const SigmaResult* r : {&b, static_cast<const SigmaResult*>(&serial)}) {
    EXPECT_EQ(a.rms, r->rms);  // bitwise
    EXPECT_EQ(a.median, r->median);
    EXPECT_EQ(a.num_inliers, r->num_inliers);
  }
}

TEST(Sigma, ImagesMatchedByNameAndMissingImagesSkipped) {
  const test::TestScene s = test::MakeTestScene(10, 12, 2000, 0.5);
  // The model numbers images differently and lacks three of them.
  Reconstruction model = test::RenumberedPosesOnly(s.gt, 100);
  for (uint32_t id : {101u, 105u, 112u}) model.images.erase(id);
  const RegisteredViews views = MatchImagesByName(model, s.gt);
  ASSERT_EQ(views.poses.size(), 9u);
  for (const auto& [obs_id, pose] : views.poses) {
    EXPECT_TRUE(obs_id != 1 && obs_id != 5 && obs_id != 12) << obs_id;
    EXPECT_TRUE(pose.C().isApprox(s.gt.images.at(obs_id).pose.C()));
  }
  const SigmaResult r = EvaluateSigma(s.gt, views.poses, {}, &views.cameras);
  const std::vector<int> lengths = TrackLengths(s.gt, views.poses);
  size_t num_obs = 0;
  for (int n : lengths) num_obs += n;
  EXPECT_EQ(r.num_tracks, lengths.size());
  EXPECT_LT(r.num_tracks, s.gt.points3D.size());  // some tracks lost their second view
  EXPECT_EQ(r.num_observations, num_obs);
  EXPECT_NEAR(r.rms / test::ExpectedSigmaRms(lengths, 0.5), 1.0, 0.04);
}

TEST(Sigma, NothingRegisteredIsNotComputable) {
  const test::TestScene s = test::MakeTestScene(11, 6, 200, 0.5);
  const SigmaResult r = EvaluateSigma(s.gt, PoseMap{});
  EXPECT_FALSE(r.Computable());
  EXPECT_EQ(r.num_tracks, 0u);
  EXPECT_EQ(r.num_observations, 0u);
}

TEST(Sigma, UsesTheGivenIntrinsics) {
  // The model's cameras (e.g. refined by a peer method) take precedence over the
  // observation model's: a principal point off by 8 px must show up in sigma.
  const test::TestScene s = test::MakeTestScene(12, 12, 1000, 0.5);
  Reconstruction model = test::RenumberedPosesOnly(s.gt, 0);
  model.cameras.at(1).params[2] += 8.0;
  const RegisteredViews views = MatchImagesByName(model, s.gt);
  const SigmaResult own = EvaluateSigma(s.gt, views.poses);
  const SigmaResult shifted = EvaluateSigma(s.gt, views.poses, {}, &views.cameras);
  EXPECT_NEAR(own.rms / test::ExpectedSigmaRms(TrackLengths(s.gt, views.poses), 0.5), 1.0, 0.04);
  EXPECT_GT(shifted.rms, 2.0 * own.rms) << shifted.rms;
}

}  // namespace
}  // namespace pgba
