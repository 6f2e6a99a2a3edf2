// IntrinsicsUncertainty (the test that decides whether a triplet BA frees its intrinsics)
// against the truth it predicts: the scatter of the focal and k that the triplet BA itself
// estimates over independent noise draws on one synthetic triplet (ring scene, SIMPLE_RADIAL
// f 800 px, k -0.08, 1280 x 960, three views 15 deg apart, 0.5 px noise).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "modules/triplets/intrinsics_uncertainty.h"
#include "modules/triplets/triplet_options.h"
#include "pgba/optim/bundle_adjuster.h"
#include "tests/local_hessian/ring_scene.h"

namespace pgba {
namespace {

// Images 1, 2, 3 of the ring and the points seen by two or more of them, observations at
// their true projections (noise is added by the caller).
Reconstruction TrueTriplet(const testing::RingSceneOptions& o) {
  const Reconstruction ring = testing::MakeRingScene(o);
  Reconstruction rec;
  rec.cameras = ring.cameras;
  for (uint32_t id : {1u, 2u, 3u}) {
    Image im = ring.images.at(id);
    im.points2D.clear();
    rec.images.emplace(id, im);
  }
  for (const auto& [pid, point] : ring.points3D) {
    std::vector<TrackElement> track;
    for (const TrackElement& el : point.track) {
      if (el.image_id > 3) continue;
      Image& im = rec.images.at(el.image_id);
      im.points2D.push_back({rec.cameras.at(1).Project(im.pose.ToCamera(point.xyz)), kNoPoint3D});
      track.push_back({el.image_id, static_cast<uint32_t>(im.points2D.size() - 1)});
    }
    if (track.size() >= 2) {
      rec.AddPoint3D(point.xyz, track);
    } else {
      for (const TrackElement& el : track) rec.images.at(el.image_id).points2D.pop_back();
    }
  }
  return rec;
}

IntrinsicsUncertainty Uncertainty(const Reconstruction& rec) {
  return EstimateIntrinsicsUncertainty(rec, {1, 2, 3}, SelectFreeIntrinsics(rec.cameras, IntrinsicsOptions()), 1, 3);
}

TEST(IntrinsicsUncertainty, PredictsTheScatterOfTheTripletBAsFocalAndK) {
  testing::RingSceneOptions o;
  o.k1 = -0.08;
  o.num_points = 1500;
  o.noise_px = 0.0;
  const Reconstruction truth = TrueTriplet(o);
  const IntrinsicsUncertainty u = Uncertainty(truth);
  ASSERT_TRUE(u.ok);
  ASSERT_EQ(u.stddev.size(), 2u);  // f, k (principal point held)

  const double noise_px = 0.5;
  const int trials = 40;
  std::mt19937_64 rng(3);
  std::normal_distribution<double> normal(0.0, noise_px);
  double sf = 0.0, sf2 = 0.0, sk = 0.0, sk2 = 0.0;
  BundleAdjustmentProblem problem;
  problem.fix_gauge = true;
  problem.gauge_anchor = 1;
  problem.gauge_scale = 3;
  problem.free_intrinsics = SelectFreeIntrinsics(truth.cameras, IntrinsicsOptions());
  BundleAdjusterOptions ba;
  ba.loss.type = LossType::kTrivial;  // the prediction is that of plain least squares
  ba.solver.function_tolerance = 1e-12;
  for (int t = 0; t < trials; ++t) {
    Reconstruction rec = truth;
    for (auto& [id, im] : rec.images)
      for (Point2D& p : im.points2D) p.xy += Eigen::Vector2d(normal(rng), normal(rng));
    const BundleAdjustmentSummary s = BundleAdjust(problem, ba, &rec);
    ASSERT_TRUE(s.usable);
    const double f = rec.cameras.at(1).params[0] - o.focal_px, k = rec.cameras.at(1).params[3] - o.k1;
    sf += f, sf2 += f * f, sk += k, sk2 += k * k;
  }
  const double sd_f = std::sqrt((sf2 - sf * sf / trials) / (trials - 1));
  const double sd_k = std::sqrt((sk2 - sk * sk / trials) / (trials - 1));
  const double ratio_f = sd_f / (noise_px * u.stddev[0]), ratio_k = sd_k / (noise_px * u.stddev[1]);
  std::printf("  predicted sd f %.3f px, k %.5f (x %.1f px noise); scatter of %d BAs: f %.3f px (%.2fx), k %.5f (%.2fx)\n",
              noise_px * u.stddev[0], noise_px * u.stddev[1], noise_px, trials, sd_f, ratio_f, sd_k, ratio_k);
  // An sd from 40 draws is itself uncertain by ~11% (1 / sqrt(2 (n - 1))): 2.5 of those.
  EXPECT_NEAR(ratio_f, 1.0, 0.28);
  EXPECT_NEAR(ratio_k, 1.0, 0.28);
  // stddev_px: the same sd times the corner's sensitivity (f: normalised radius of the corner).
  const Camera& cam = truth.cameras.at(1);
  EXPECT_NEAR(u.stddev_px[0], u.stddev[0] * CornerPixelSensitivity(cam, Eigen::VectorXd::Unit(cam.params.size(), 0)), 1e-9 * u.stddev_px[0]);
  EXPECT_DOUBLE_EQ(u.max_stddev_px, std::max(u.stddev_px[0], u.stddev_px[1]));
}

TEST(IntrinsicsUncertainty, CornerSensitivityOfTheFocalIsTheCornersNormalisedRadius) {
  Camera cam;
  cam.model = CameraModel::kSimplePinhole;
  cam.width = 1000;
  cam.height = 600;
  cam.params = {1200.0, 400.0, 300.0};
  // Farthest corner (1000, 600) or (1000, 0): 600 px, 300 px from the principal point.
  EXPECT_NEAR(CornerPixelSensitivity(cam, Eigen::VectorXd::Unit(cam.params.size(), 0)), std::hypot(600.0, 300.0) / 1200.0, 1e-7);
  EXPECT_NEAR(CornerPixelSensitivity(cam, Eigen::VectorXd::Unit(cam.params.size(), 1)), 1.0, 1e-7);  // the principal point moves every pixel
}

// The triplet BA's decision (TripletOptions::intrinsics_max_sd_px): the wide triplet above
// determines its focal and k, the same ring seen through a 10x longer lens from 10x farther
// (field of view 9 deg: focal and depth trade) does not.
TEST(IntrinsicsUncertainty, AWideTripletDeterminesItsIntrinsicsANarrowOneDoesNot) {
  testing::RingSceneOptions wide;
  wide.k1 = -0.08;
  wide.num_points = 1500;
  testing::RingSceneOptions narrow = wide;
  narrow.focal_px = 8000.0;
  narrow.ring_radius = 80.0;
  const IntrinsicsUncertainty w = Uncertainty(TrueTriplet(wide)), n = Uncertainty(TrueTriplet(narrow));
  std::printf("  largest sd at the corner per px of noise: wide %.3f px, narrow %.1f px\n", w.max_stddev_px,
              n.max_stddev_px);
  const double threshold = TripletOptions().intrinsics_max_sd_px;
  EXPECT_LT(w.max_stddev_px, threshold);
  EXPECT_GT(n.max_stddev_px, threshold);
}

TEST(IntrinsicsUncertainty, TheThresholdMustBePositive) {
  TripletOptions o;
  EXPECT_EQ(o.Check(), "");
  for (double bad : {0.0, -1.0, std::nan("")}) {
    o.intrinsics_max_sd_px = bad;
    EXPECT_NE(o.Check().find("intrinsics_max_sd_px"), std::string::npos) << bad;
  }
}

}  // namespace
}  // namespace pgba
