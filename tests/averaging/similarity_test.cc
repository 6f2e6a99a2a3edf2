#include "averaging/similarity.h"

#include <gtest/gtest.h>

#include "pgba/geometry/rotation.h"
#include "relative_motion_fixture.h"

namespace pgba {
namespace {

// Without noise every triplet's known global->local similarity is recovered to machine
// precision, including the triplets of the aerial strips whose three centres are nearly
// collinear (their rotation comes from the cameras, not from the centres).
TEST(TripletSimilarity, RecoversKnownSimilarityExactly) {
  for (test::Layout layout : {test::Layout::kOrbit, test::Layout::kAerial, test::Layout::kVideo}) {
    const test::GroundTruth gt = test::MakeLayout(layout, 3);
    test::NoiseModel noise;
    noise.rotation_deg = noise.direction_deg = noise.centre_rel = 0.0;
    test::RelativeMotions m = test::MakeRelativeMotions(gt, noise, 4);
    const std::vector<TripletSimilarityFit> fits = ComputeTripletSimilarities(gt.poses, &m.triplets);
    ASSERT_EQ(fits.size(), m.triplets.size());
    for (size_t t = 0; t < fits.size(); ++t) {
      ASSERT_TRUE(fits[t].valid);
      const Sim3& d = m.triplets[t].global_to_local;
      const Sim3& truth = m.true_global_to_local[t];
      EXPECT_NEAR(d.s / truth.s, 1.0, 1e-12);
      EXPECT_LT(RotationAngleDeg(d.R, truth.R), 1e-9);
      EXPECT_LT((d.t - truth.t).norm(), 1e-10 * (1.0 + truth.t.norm()));
      EXPECT_LT(fits[t].rotation_residual_deg, 1e-9);
      EXPECT_LT(fits[t].centre_residual_rel, 1e-12);
      // Paper eq. 4: d applied to the global poses gives the local poses.
      for (int k = 0; k < 3; ++k) {
        const Pose local = d.Apply(gt.poses.at(m.triplets[t].image_ids[k]));
        EXPECT_LT(RotationAngleDeg(local.R(), m.triplets[t].local_poses[k].R()), 1e-9);
        EXPECT_LT((local.C() - m.triplets[t].local_poses[k].C()).norm(), 1e-10 * truth.s * gt.extent);
      }
    }
  }
}

// Exactly collinear global centres: the centres alone cannot give the rotation about their
// line, the cameras do.
TEST(TripletSimilarity, CollinearCentres) {
  std::mt19937_64 rng(3);
  std::map<uint32_t, Pose> poses;
  for (uint32_t id = 0; id < 3; ++id)
    poses[id] = Pose::FromRC(RandomRotation(rng), Eigen::Vector3d(1.0 + 2.0 * id * id, 0.5, -3.0));
  Sim3 truth;
  truth.s = 0.37;
  truth.R = RandomRotation(rng);
  truth.t = Eigen::Vector3d(4, -2, 9);
  LocalMotion t;
  t.image_ids = {0, 1, 2};
  t.local_poses.resize(3);
  for (int k = 0; k < 3; ++k) t.local_poses[k] = truth.Apply(poses[k]);
  const TripletSimilarityFit fit = EstimateTripletSimilarity(t, poses);
  ASSERT_TRUE(fit.valid);
  EXPECT_NEAR(fit.global_to_local.s, truth.s, 1e-12);
  EXPECT_LT(RotationAngleDeg(fit.global_to_local.R, truth.R), 1e-9);
  EXPECT_LT((fit.global_to_local.t - truth.t).norm(), 1e-10);
}

// Noise on the local rotations: alpha is their average, the residual reports the misfit.
TEST(TripletSimilarity, ReportsResiduals) {
  const test::GroundTruth gt = test::MakeLayout(test::Layout::kOrbit, 1);
  test::NoiseModel noise;
  noise.rotation_deg = 1.0;
  noise.centre_rel = 0.01;
  test::RelativeMotions m = test::MakeRelativeMotions(gt, noise, 2);
  const std::vector<TripletSimilarityFit> fits = ComputeTripletSimilarities(gt.poses, &m.triplets);
  double rot_max = 0.0, centre_max = 0.0;
  for (size_t t = 0; t < fits.size(); ++t) {
    ASSERT_TRUE(fits[t].valid);
    rot_max = std::max(rot_max, fits[t].rotation_residual_deg);
    centre_max = std::max(centre_max, fits[t].centre_residual_rel);
    EXPECT_NEAR(fits[t].global_to_local.s / m.true_global_to_local[t].s, 1.0, 0.05);
    EXPECT_LT(RotationAngleDeg(fits[t].global_to_local.R, m.true_global_to_local[t].R), 2.0);
  }
  EXPECT_GT(rot_max, 0.1);
  EXPECT_LT(rot_max, 5.0);
  EXPECT_GT(centre_max, 0.001);
  EXPECT_LT(centre_max, 0.1);
}

// Coincident global centres give no scale: invalid, no crash.
TEST(TripletSimilarity, DegenerateIsInvalid) {
  std::map<uint32_t, Pose> poses;
  for (uint32_t id = 0; id < 3; ++id) poses[id] = Pose::FromRC(Eigen::Matrix3d::Identity(), Eigen::Vector3d(1, 2, 3));
  LocalMotion t;
  t.image_ids = {0, 1, 2};
  t.local_poses.resize(3);
  t.local_poses[1] = Pose::FromRC(Eigen::Matrix3d::Identity(), Eigen::Vector3d(1, 0, 0));
  EXPECT_FALSE(EstimateTripletSimilarity(t, poses).valid);
}

}  // namespace
}  // namespace pgba
