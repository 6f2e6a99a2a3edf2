// Global initialisation on the view graphs of the synthetic scenes (modules/synthetic): the
// pairs and triplets are those a front end would find from the scene's tracks (images
// sharing enough tracks), their relative motions the true ones plus noise.
#include <gtest/gtest.h>

#include "averaging/global_init.h"
#include "averaging/outlier_injection.h"
#include "relative_motion_fixture.h"
#include "synthetic/synthetic_scene.h"

namespace pgba {
namespace {

struct Outcome {
  GlobalInitResult result;
  double rot_median, rot_max, centre_median, centre_max;
};

Outcome RunScene(SyntheticScenario scenario, const test::NoiseModel& noise, double outlier_fraction = 0.0) {
  SyntheticOptions so;
  so.scenario = scenario;
  so.seed = 3;
  const SyntheticScene scene = GenerateSyntheticScene(so);
  const test::RelativeMotions m = test::MakeRelativeMotionsFromTracks(scene.gt, noise, 4);
  OutlierInjectionOptions outliers;
  outliers.fraction = outlier_fraction;
  outliers.seed = 5;
  const CorruptedRelativeMotions c = CorruptRelativeMotions(outliers, m.pairs, m.triplets);
  Outcome o{RunGlobalInitialisation(scene.input, c.pairs, c.triplets, GlobalInitOptions(), &c.rotation_measurements),
            0, 0, 0, 0};
  std::map<uint32_t, Pose> gt;
  for (const auto& [id, im] : scene.gt.images) gt[id] = im.pose;
  std::map<uint32_t, Eigen::Matrix3d> R;
  std::map<uint32_t, Eigen::Vector3d> C;
  for (const auto& [id, p] : o.result.poses) {
    R[id] = p.R();
    C[id] = p.C();
  }
  const std::vector<double> rot = test::RotationErrorsDeg(R, gt);
  const std::vector<double> centre = test::CentreErrorsRel(C, gt, scene.extent, &R);
  o.rot_median = test::Median(rot);
  o.rot_max = test::Max(rot);
  o.centre_median = test::Median(centre);
  o.centre_max = test::Max(centre);
  std::cout << SyntheticScenarioName(scenario) << " (" << scene.gt.images.size() << " images, " << m.pairs.size()
            << " pairs, " << m.triplets.size() << " triplets, outliers " << outlier_fraction
            << "): rotation error median " << o.rot_median << " max " << o.rot_max << " deg, centre error median "
            << o.centre_median << " max " << o.centre_max << " of extent, " << o.result.stats.seconds_total << " s\n";
  EXPECT_TRUE(o.result.success) << o.result.message;
  EXPECT_EQ(o.result.poses.size(), scene.gt.images.size());
  EXPECT_TRUE(o.result.images_dropped.empty());
  return o;
}

class SyntheticInit : public ::testing::TestWithParam<SyntheticScenario> {};

// Relative rotations and directions with 0.1 deg noise, triplet centres with 0.2%: every
// image registered, rotation error median < 0.1 deg and max < 0.5 deg, centre error median
// < 1% of the extent.
TEST_P(SyntheticInit, AccurateOnTheScenesViewGraph) {
  test::NoiseModel noise;
  noise.rotation_deg = noise.direction_deg = 0.1;
  noise.centre_rel = 0.002;
  const Outcome o = RunScene(GetParam(), noise);
  EXPECT_LT(o.rot_median, 0.1);
  EXPECT_LT(o.rot_max, 0.5);
  EXPECT_LT(o.centre_median, 0.01);
}

INSTANTIATE_TEST_SUITE_P(Scenes, SyntheticInit,
                         ::testing::Values(SyntheticScenario::kOrbit, SyntheticScenario::kAerial,
                                           SyntheticScenario::kPlanar));

// The long-focal open ring (2 degree field of view, loop withheld): every image registered,
// the ring chained without breaking. Noise scaled to the lens (0.005 deg ~ 14 px).
TEST(SyntheticInit, LongFocalRingChains) {
  test::NoiseModel noise;
  noise.rotation_deg = noise.direction_deg = 0.005;
  noise.centre_rel = 0.002;
  const Outcome o = RunScene(SyntheticScenario::kLongFocal, noise);
  EXPECT_EQ(o.result.stats.triplets_outside_component, 0);
}

// 10% and 20% of the relative rotations (pairs and triplets) replaced by random ones on
// the orbit: median rotation error < 0.5 deg.
TEST(SyntheticInit, OrbitWithRotationOutliers) {
  test::NoiseModel noise;
  noise.rotation_deg = noise.direction_deg = 0.1;
  noise.centre_rel = 0.002;
  for (double fraction : {0.1, 0.2}) {
    const Outcome o = RunScene(SyntheticScenario::kOrbit, noise, fraction);
    EXPECT_LT(o.rot_median, 0.5);
    EXPECT_LT(o.centre_median, 0.01);
  }
}

}  // namespace
}  // namespace pgba
