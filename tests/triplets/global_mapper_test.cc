// The global mapper (pairs -> triplets -> averaging) end to end on small synthetic scenes:
// tracks with 0.5 px noise and 2% outlier observations from modules/synthetic, poses
// compared with the scene's ground truth (rotation error after the best global rotation,
// centre error after a Sim(3) alignment, as fractions of the extent).
#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "evaluation/ground_truth.h"
#include "triplets/triplet_selection.h"
#include "mapper/pointless_mapper.h"
#include "pgba/geometry/rotation.h"
#include "synthetic/synthetic_scene.h"
#include "tests/averaging/relative_motion_fixture.h"

namespace pgba {
namespace {

struct Outcome {
  GlobalMapperResult result;
  Report report;
  double rot_median = 0, rot_max = 0, centre_median = 0;
  // The same errors by `pgba evaluate`'s protocol (evaluation/ground_truth.h): the rotations
  // under the Sim(3) that aligns the centres. On a nearly straight path that alignment's roll
  // about the path is set by the centres' small lateral offsets, so centre errors show up
  // as rotation errors of every image.
  double eval_rot_median = 0, eval_rot_max = 0, eval_centre_median = 0;
  int triplet_components = 0;
};

SyntheticScene Scene(SyntheticScenario scenario, int num_images, double noise_px = 0.5, double outliers = 0.02) {
  SyntheticOptions so;
  so.scenario = scenario;
  so.seed = 1;
  so.noise_px = noise_px;
  so.outlier_fraction = outliers;
  so.num_images = num_images;
  if (scenario == SyntheticScenario::kAerial) so.num_strips = 2;
  return GenerateSyntheticScene(so);
}

Outcome RunMapper(const SyntheticScene& scene, const GlobalMapperOptions& options = {}) {
  Outcome o;
  o.result = RunGlobalMapper(scene.input, options, &o.report);
  std::map<uint32_t, Pose> gt;
  for (const auto& [id, im] : scene.gt.images) gt[id] = im.pose;
  std::map<uint32_t, Eigen::Matrix3d> R;
  std::map<uint32_t, Eigen::Vector3d> C;
  for (const auto& [id, p] : o.result.init.poses) {
    R[id] = p.R();
    C[id] = p.C();
  }
  const std::vector<double> rot = test::RotationErrorsDeg(R, gt);
  o.rot_median = test::Median(rot);
  o.rot_max = test::Max(rot);
  o.centre_median = test::Median(test::CentreErrorsRel(C, gt, scene.extent, &R));
  std::vector<std::array<uint32_t, 3>> ids;
  for (const LocalMotion& t : o.result.init.triplets) ids.push_back(TripletImageIds(t));
  TripletGraphComponents(ids, &o.triplet_components);
  Reconstruction model = scene.input;
  std::vector<uint32_t> posed;
  for (const auto& [id, p] : o.result.init.poses) {
    model.images.at(id).pose = p;
    posed.push_back(id);
  }
  model.KeepImages(posed);
  const GroundTruthErrors eval = CompareToGroundTruth(model, scene.gt);
  o.eval_rot_median = eval.rot_err_deg_median;
  o.eval_rot_max = eval.rot_err_deg_max;
  o.eval_centre_median = eval.center_err_rel_median;
  std::cout << scene.gt.images.size() << " images: " << o.result.init.poses.size() << " registered, "
            << o.result.init.triplets.size() << " triplets, rotation error median " << o.rot_median << " max "
            << o.rot_max << " deg, centre error median " << o.centre_median << " of extent; evaluate: rotation "
            << o.eval_rot_median << " / " << o.eval_rot_max << " deg, centre " << o.eval_centre_median << "\n";
  return o;
}

void ExpectAccurate(const SyntheticScene& scene, const Outcome& o, double rot_median, double rot_max,
                    double centre_median) {
  EXPECT_EQ(o.result.init.poses.size(), scene.gt.images.size());
  EXPECT_TRUE(o.result.init.images_dropped.empty());
  EXPECT_EQ(o.triplet_components, 1);
  EXPECT_LT(o.rot_median, rot_median);
  EXPECT_LT(o.rot_max, rot_max);
  EXPECT_LT(o.centre_median, centre_median);
}

// The initial solution's targets on the orbit and the aerial block: every image registered, one
// triplet component, rotation error median < 0.1 deg and max < 0.5 deg, centre error
// median < 1% of the extent.
TEST(GlobalMapper, OrbitAccurate) {
  const SyntheticScene scene = Scene(SyntheticScenario::kOrbit, 0);
  ExpectAccurate(scene, RunMapper(scene), 0.1, 0.5, 0.01);
}

TEST(GlobalMapper, AerialAccurate) {
  const SyntheticScene scene = Scene(SyntheticScenario::kAerial, 0);
  ExpectAccurate(scene, RunMapper(scene), 0.1, 0.5, 0.01);
}

// A planar wall: every pair's essential matrix has a twin (the second decomposition of the
// plane's homography). Noise-free, the init must be exact: before the pairs were checked
// against the triplets the twins biased rotation averaging by 0.25 deg (median).
TEST(GlobalMapper, PlanarNoiseFreeIsExact) {
  const SyntheticScene scene = Scene(SyntheticScenario::kPlanar, 30, 0.0, 0.0);
  const Outcome o = RunMapper(scene);
  EXPECT_GT(o.result.init.stats.pairs_inconsistent, 0);  // the twins exist and are found
  ExpectAccurate(scene, o, 1e-3, 1e-3, 1e-4);
}

// With noise, on 30 frames: the same targets (0.1 deg, 0.5 deg, 1%). Tight: the
// three-view geometry of a plane seen with a 35 x 54 degree field of view confuses pitch and
// yaw with the translation over depth (rms 0.15 deg per triplet), and these errors drift
// along the strip; the default 60-frame video drifts to a median of ~0.18 deg.
TEST(GlobalMapper, PlanarWithNoise) {
  const SyntheticScene scene = Scene(SyntheticScenario::kPlanar, 30);
  ExpectAccurate(scene, RunMapper(scene), 0.1, 0.5, 0.01);
}

// The default 60-frame planar video. Its triplets' baseline ratios carry the plane's
// rotation / translation-over-depth ambiguity (4-7% per triplet), which translation averaging
// chained into a drifting scale: centre error 1.5% of the extent and, by the evaluation's
// protocol, 1.95 deg of rotation error (the centres' Sim(3) tilted). The centres refined on
// the tracks with the averaged rotations fixed (averaging/track_positioning.h, off by
// default, see there) are at 0.15%,
// and the evaluation's rotation error at 0.29 deg median. Not reachable: < 0.1 deg. The
// maximum-likelihood solution of the same observations (a point-based BA started from the
// truth) has 0.44 deg by the evaluation's protocol and 0.115 deg after the best global
// rotation; what is left here is the drift of the rotations averaged from triplets that
// each confuse pitch and yaw with the translation by 0.1 deg (0.18 deg after 60 frames).
TEST(GlobalMapper, PlanarSixtyFrames) {
  const SyntheticScene scene = Scene(SyntheticScenario::kPlanar, 60);
  GlobalMapperOptions options;
  options.global_init.track_positioning.enabled = true;
  const Outcome o = RunMapper(scene, options);
  ExpectAccurate(scene, o, 0.25, 0.5, 0.005);
  EXPECT_LT(o.eval_centre_median, 0.005);
  EXPECT_LT(o.eval_rot_median, 0.5);
  EXPECT_LT(o.eval_rot_max, 1.0);
  EXPECT_TRUE(o.result.init.stats.track_positioning.ran);
}

// 10% and 20% of the relative rotations (pairs and triplets) replaced by random ones on the
// orbit: every image registered, median rotation error < 0.5 deg (in fact at the
// noise level: the outliers are found). The corrupted relative rotations are excluded as
// edges; the triplets whose rotations were corrupted as measurements keep their local
// geometry (outlier_injection.h), so none is dropped and the triplet graph stays whole.
// Before, the corrupted triplets were rejected and cut the orbit's triplet chain: at 20%,
// 37 of 70 images were registered.
TEST(GlobalMapper, OrbitWithRotationOutliers) {
  const SyntheticScene scene = Scene(SyntheticScenario::kOrbit, 0);
  for (double fraction : {0.1, 0.2}) {
    GlobalMapperOptions options;
    options.rotation_outliers.fraction = fraction;
    const Outcome o = RunMapper(scene, options);
    const GlobalInitStats& s = o.result.init.stats;
    const int pairs_corrupted = static_cast<int>(o.result.outliers_injected.pairs.size());
    const int triplets_corrupted = static_cast<int>(o.result.outliers_injected.triplets.size());
    EXPECT_EQ(o.result.init.poses.size(), scene.gt.images.size()) << fraction;
    EXPECT_TRUE(o.result.init.images_dropped.empty()) << fraction;
    EXPECT_EQ(o.triplet_components, 1) << fraction;
    EXPECT_LT(o.rot_median, 0.5) << fraction;
    EXPECT_LT(o.rot_max, 0.5) << fraction;
    EXPECT_LT(o.centre_median, 0.01) << fraction;
    // Each corrupted triplet carries two wrong relative rotations; the corrupted pairs are
    // caught by the pair validation or excluded by their residual.
    EXPECT_GT(triplets_corrupted, 0) << fraction;
    EXPECT_GE(s.rotation.num_outliers, 2 * triplets_corrupted) << fraction;
    EXPECT_LE(s.rotation.num_outliers, 2 * triplets_corrupted + pairs_corrupted + 5) << fraction;
    EXPECT_EQ(s.triplets_rotation_outliers, 0) << fraction;
  }
}

// The benchmark's variant: the corrupted triplets' local poses themselves are wrong. They
// are rejected (their rotations disagree with the averaged ones) and, by default, dropped;
// the averaged rotations of the images still registered stay at the noise level.
TEST(GlobalMapper, OrbitWithCorruptedTripletPoses) {
  const SyntheticScene scene = Scene(SyntheticScenario::kOrbit, 0);
  GlobalMapperOptions options;
  options.rotation_outliers.fraction = 0.1;
  options.rotation_outliers.triplet_corruption = TripletCorruption::kLocalPoses;
  const Outcome o = RunMapper(scene, options);
  const GlobalInitStats& s = o.result.init.stats;
  const int triplets_corrupted = static_cast<int>(o.result.outliers_injected.triplets.size());
  EXPECT_GT(triplets_corrupted, 0);
  EXPECT_GE(s.triplets_rotation_outliers, triplets_corrupted * 9 / 10);
  EXPECT_LE(s.triplets_rotation_outliers, triplets_corrupted + 2);
  EXPECT_GE(o.result.init.poses.size(), scene.gt.images.size() / 2);
  EXPECT_LT(o.rot_median, 0.1);
}

// Same input and options: the same triplets and the same poses. Up to rounding: the
// triplet BAs (Ceres / Eigen on buffers whose alignment varies from run to run) differ in
// the last bits between runs, which the averaging carries through at the 1e-12 level.
TEST(GlobalMapper, Deterministic) {
  const SyntheticScene scene = Scene(SyntheticScenario::kOrbit, 0);
  const Outcome a = RunMapper(scene), b = RunMapper(scene);
  ASSERT_EQ(a.result.init.poses.size(), b.result.init.poses.size());
  for (const auto& [id, p] : a.result.init.poses) {
    ASSERT_TRUE(b.result.init.poses.count(id)) << id;
    EXPECT_LT(RotationAngleDeg(p.R(), b.result.init.poses.at(id).R()), 1e-9) << id;
    EXPECT_LT((p.C() - b.result.init.poses.at(id).C()).norm(), 1e-9 * scene.extent) << id;
  }
  ASSERT_EQ(a.result.init.triplets.size(), b.result.init.triplets.size());
  for (size_t t = 0; t < a.result.init.triplets.size(); ++t)
    EXPECT_EQ(a.result.init.triplets[t].image_ids, b.result.init.triplets[t].image_ids);
  EXPECT_EQ(a.result.pairs.size(), b.result.pairs.size());
}

// Tracks whose view graph falls apart: every track of an orbit is cut where it passes
// between the first images and the others, so the last images form their own component.
// The largest one is the result's initialisation (the others' images not in it), the small
// one a model of its own: every image is registered in one of them.
TEST(GlobalMapper, DisconnectedViewGraphGivesAModelPerComponent) {
  SyntheticScene scene = Scene(SyntheticScenario::kOrbit, 0);
  std::set<uint32_t> small;
  for (const auto& [id, im] : scene.input.images)
    if (small.size() < 5 && id > 3) small.insert(id);  // a run of ring neighbours
  Reconstruction& rec = scene.input;
  std::map<uint64_t, Point3D> points;
  uint64_t next = 1;
  for (const auto& [pid, point] : rec.points3D) {
    Point3D parts[2];
    for (const TrackElement& e : point.track) parts[small.count(e.image_id)].track.push_back(e);
    for (Point3D& part : parts) {
      if (part.track.size() < 2) {
        for (const TrackElement& e : part.track) rec.images.at(e.image_id).points2D[e.point2D_idx].point3D_id = kNoPoint3D;
        continue;
      }
      part.point3D_id = next++;
      for (const TrackElement& e : part.track)
        rec.images.at(e.image_id).points2D[e.point2D_idx].point3D_id = static_cast<int64_t>(part.point3D_id);
      points.emplace(part.point3D_id, part);
    }
  }
  rec.points3D = std::move(points);
  ASSERT_EQ(rec.CheckConsistency(), "");
  Outcome o = RunMapper(scene);
  EXPECT_EQ(o.result.init.poses.size(), scene.input.images.size() - small.size());
  std::set<std::string> expected, dropped(o.result.init.images_dropped.begin(), o.result.init.images_dropped.end());
  for (uint32_t id : small) expected.insert(scene.input.images.at(id).name);
  EXPECT_EQ(dropped, expected);
  for (uint32_t id : small) EXPECT_FALSE(o.result.init.poses.count(id));
  EXPECT_TRUE(o.report["images_dropped"].empty()) << o.report["images_dropped"];
  EXPECT_EQ(o.report["images_registered"], scene.input.images.size());
  const nlohmann::json& components = o.report["stages"]["global_init"]["components"];
  ASSERT_EQ(components.size(), 2u);
  EXPECT_EQ(components[0]["images_registered"], scene.input.images.size() - small.size());
  EXPECT_EQ(components[1]["images_registered"], small.size());
}

}  // namespace
}  // namespace pgba
