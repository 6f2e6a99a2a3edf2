// Track positioning (centres refined on the tracks, rotations held fixed) on the synthetic
// scenes of modules/synthetic: true rotations, centres perturbed the way a drifting triplet
// chain perturbs them.
#include "averaging/track_positioning.h"

#include <gtest/gtest.h>

#include "pgba/geometry/rotation.h"
#include "pgba/util/error.h"
#include "relative_motion_fixture.h"
#include "synthetic/synthetic_scene.h"

namespace pgba {
namespace {

SyntheticScene Scene(SyntheticScenario scenario, int num_images) {
  SyntheticOptions so;
  so.scenario = scenario;
  so.seed = 2;
  so.noise_px = 0.5;
  so.outlier_fraction = 0.02;
  so.num_images = num_images;
  return GenerateSyntheticScene(so);
}

std::map<uint32_t, Pose> TruePoses(const SyntheticScene& scene) {
  std::map<uint32_t, Pose> gt;
  for (const auto& [id, im] : scene.gt.images) gt[id] = im.pose;
  return gt;
}

// The true poses with a smooth scale drift along the image order (5% over the sequence) and
// 1% of the extent of random centre noise.
std::map<uint32_t, Pose> Drifted(const std::map<uint32_t, Pose>& gt, double extent) {
  std::mt19937_64 rng(3);
  std::normal_distribution<double> n01(0.0, 1.0);
  std::map<uint32_t, Pose> out;
  const Eigen::Vector3d C0 = gt.begin()->second.C();
  int k = 0;
  for (const auto& [id, p] : gt) {
    const double drift = 1.0 + 0.05 * k++ / static_cast<double>(gt.size());
    const Eigen::Vector3d noise(n01(rng), n01(rng), n01(rng));
    out[id] = Pose::FromRC(p.R(), C0 + drift * (p.C() - C0) + 0.01 * extent * noise);
  }
  return out;
}

double MedianCentreError(const std::map<uint32_t, Pose>& poses, const std::map<uint32_t, Pose>& gt, double extent) {
  std::map<uint32_t, Eigen::Vector3d> C;
  std::map<uint32_t, Eigen::Matrix3d> R;
  for (const auto& [id, p] : poses) {
    C[id] = p.C();
    R[id] = p.R();
  }
  return test::Median(test::CentreErrorsRel(C, gt, extent, &R));
}

// On the planar video (the scene whose triplet chain drifts most): the centres come back to
// the noise level, the rotations are not touched, and the result is normalised like
// translation averaging's (centroid 0, median triplet scale 1).
TEST(TrackPositioning, RecoversCentresWithRotationsFixed) {
  const SyntheticScene scene = Scene(SyntheticScenario::kPlanar, 30);
  const std::map<uint32_t, Pose> gt = TruePoses(scene);
  std::map<uint32_t, Pose> poses = Drifted(gt, scene.extent);
  const double before = MedianCentreError(poses, gt, scene.extent);
  const test::RelativeMotions m = test::MakeRelativeMotionsFromTracks(scene.gt, test::NoiseModel(), 4);
  TrackPositioningOptions options;
  options.enabled = true;
  TrackPositioningSummary summary;
  ASSERT_TRUE(PositionOnTracks(scene.input, m.triplets, options, &poses, &summary))
      << summary.message;
  const double after = MedianCentreError(poses, gt, scene.extent);
  std::cout << "planar 30: centre error median " << before << " -> " << after << " of extent, " << summary.iterations
            << " iterations, RMS " << summary.initial_rms_px << " -> " << summary.final_rms_px << " px, "
            << summary.seconds << " s\n";
  EXPECT_TRUE(summary.ran);
  EXPECT_GT(before, 0.005);
  EXPECT_LT(after, 0.002);
  EXPECT_LT(summary.final_rms_px, 0.7);
  EXPECT_GT(summary.num_points, 0.8 * scene.input.points3D.size());  // most tracks used
  for (const auto& [id, p] : poses) EXPECT_LT(RotationAngleDeg(p.R(), gt.at(id).R()), 1e-9);
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const auto& [id, p] : poses) centroid += p.C();
  EXPECT_LT((centroid / poses.size()).norm(), 1e-9 * scene.extent);
  std::vector<double> lambdas;
  for (const LocalMotion& t : m.triplets) {
    double local = 0, global = 0;
    for (int a = 0; a < 3; ++a) {
      local += (t.local_poses[a].C() - t.local_poses[(a + 1) % 3].C()).norm();
      global += (poses.at(t.image_ids[a]).C() - poses.at(t.image_ids[(a + 1) % 3]).C()).norm();
    }
    lambdas.push_back(local / global);
  }
  EXPECT_NEAR(test::Median(lambdas), 1.0, 0.02);
}

// Disabled, or nothing to position on (no tracks): false, the poses untouched.
TEST(TrackPositioning, NothingToDoLeavesPosesUntouched) {
  const SyntheticScene scene = Scene(SyntheticScenario::kOrbit, 12);
  const std::map<uint32_t, Pose> gt = TruePoses(scene);
  std::map<uint32_t, Pose> poses = Drifted(gt, scene.extent);
  const std::map<uint32_t, Pose> start = poses;
  TrackPositioningOptions off;
  off.enabled = false;
  TrackPositioningSummary summary;
  EXPECT_FALSE(PositionOnTracks(scene.input, {}, off, &poses, &summary));
  EXPECT_FALSE(summary.ran);
  Reconstruction no_tracks = scene.input;
  no_tracks.points3D.clear();
  for (auto& [id, im] : no_tracks.images)
    for (Point2D& p : im.points2D) p.point3D_id = kNoPoint3D;
  TrackPositioningOptions on;
  on.enabled = true;
  EXPECT_FALSE(PositionOnTracks(no_tracks, {}, on, &poses, &summary));
  EXPECT_FALSE(summary.message.empty());
  for (const auto& [id, p] : poses) {
    EXPECT_EQ(p.C(), start.at(id).C());
    EXPECT_EQ(p.q().coeffs(), start.at(id).q().coeffs());
  }
  TrackPositioningOptions bad;
  bad.loss.scale = 0.0;
  EXPECT_THROW(PositionOnTracks(scene.input, {}, bad, &poses), InputError);
}

}  // namespace
}  // namespace pgba
