// JoinComponents on a synthetic orbit (40 images, 0.5 px noise) split into models by hand: an
// image left out of a model joins it by absolute pose, two models holding the same points
// are merged by the similarity those points give, an image whose verified pairs disagree
// with the pose it gets is not joined (with the reason), one without a verified pair is named
// as such; AlignModels recovers a known similarity and refuses models without shared points.
#include <gtest/gtest.h>

#include <cmath>

#include "evaluation/ground_truth.h"
#include "mapper/components.h"
#include "mapper/pointless_mapper.h"
#include "mapper/model_merging.h"
#include "pgba/geometry/rotation.h"
#include "pgba/scene/triangulate_model.h"
#include "synthetic/synthetic_scene.h"

namespace pgba {
namespace {

SyntheticScene Orbit() {
  SyntheticOptions so;
  so.scenario = SyntheticScenario::kOrbit;
  so.seed = 5;
  so.num_images = 40;
  so.noise_px = 0.5;
  return GenerateSyntheticScene(so);
}

// The true two-view rotation of every pair of images sharing at least 30 tracks.
std::vector<TwoViewGeometry> TruePairs(const Reconstruction& gt) {
  std::map<std::pair<uint32_t, uint32_t>, int> shared;
  for (const auto& [id, point] : gt.points3D)
    for (size_t a = 0; a < point.track.size(); ++a)
      for (size_t b = a + 1; b < point.track.size(); ++b)
        ++shared[std::minmax(point.track[a].image_id, point.track[b].image_id)];
  std::vector<TwoViewGeometry> pairs;
  for (const auto& [ids, n] : shared) {
    if (n < 30) continue;
    TwoViewGeometry p;
    p.image_id1 = ids.first;
    p.image_id2 = ids.second;
    const Pose& p1 = gt.images.at(ids.first).pose;
    const Pose& p2 = gt.images.at(ids.second).pose;
    p.R_21 = p2.R() * p1.R().transpose();
    p.t_21 = (p2.t() - p.R_21 * p1.t()).normalized();
    p.num_tracks = n;
    pairs.push_back(p);
  }
  return pairs;
}

Sim3 SomeSimilarity() {
  Sim3 s;
  s.s = 2.5;
  s.R = ExpSO3(Eigen::Vector3d(0.3, -0.2, 0.5));
  s.t = Eigen::Vector3d(4.0, -1.0, 2.0);
  return s;
}

GlobalInitResult ModelOf(const Reconstruction& gt, const std::vector<uint32_t>& ids, const Sim3& frame) {
  GlobalInitResult m;
  m.success = true;
  for (uint32_t id : ids) m.poses[id] = frame.Apply(gt.images.at(id).pose);
  return m;
}

double MaxRotationErrorDeg(const Reconstruction& tracks, const GlobalInitResult& model, const Reconstruction& gt) {
  const GroundTruthErrors e = CompareToGroundTruth(TriangulateModel(tracks, model.poses), gt);
  EXPECT_TRUE(e.ok);
  EXPECT_EQ(e.num_common, model.poses.size());
  return e.rot_err_deg_max;
}

TEST(JoinComponents, LeftOutImageJoinsAndModelsSharingPointsMerge) {
  const SyntheticScene scene = Orbit();
  const std::vector<TwoViewGeometry> pairs = TruePairs(scene.gt);
  std::vector<uint32_t> first, second;
  for (const auto& [id, image] : scene.gt.images) (id % 2 ? first : second).push_back(id);
  const uint32_t left_out = first[3];
  first.erase(first.begin() + 3);
  std::vector<GlobalInitResult> models = {ModelOf(scene.gt, first, Sim3()),
                                          ModelOf(scene.gt, second, SomeSimilarity())};
  const ComponentJoiningResult r = JoinComponents(scene.input, pairs, ComponentJoiningOptions(), &models);
  ASSERT_EQ(models.size(), 1u);
  EXPECT_EQ(models[0].poses.size(), scene.gt.images.size());
  EXPECT_TRUE(models[0].images_dropped.empty());
  ASSERT_EQ(r.merges.size(), 1u);
  EXPECT_GE(r.merges[0].alignment.inliers, 20);
  EXPECT_TRUE(r.joined.count(left_out));
  EXPECT_TRUE(r.not_joined.empty());
  const double error = MaxRotationErrorDeg(scene.input, models[0], scene.gt);
  std::printf("joined and merged: %d rounds, %d of %d shared points, rotation error max %.4f deg\n", r.rounds,
              r.merges[0].alignment.inliers, r.merges[0].alignment.shared_points, error);
  EXPECT_LT(error, 0.1);
}

TEST(JoinComponents, ImagesWithoutAgreeingPairsAreNamedNotJoined) {
  const SyntheticScene scene = Orbit();
  std::vector<TwoViewGeometry> pairs = TruePairs(scene.gt);
  std::vector<uint32_t> ids;
  for (const auto& [id, image] : scene.gt.images) ids.push_back(id);
  const uint32_t wrong = ids[10], lonely = ids[20];
  std::vector<TwoViewGeometry> kept;
  for (TwoViewGeometry& p : pairs) {
    if (p.image_id1 == lonely || p.image_id2 == lonely) continue;
    if (p.image_id1 == wrong || p.image_id2 == wrong) p.R_21 = ExpSO3(Eigen::Vector3d(0, 0.35, 0)) * p.R_21;
    kept.push_back(p);
  }
  ids.erase(ids.begin() + 20);
  ids.erase(ids.begin() + 10);
  std::vector<GlobalInitResult> models = {ModelOf(scene.gt, ids, Sim3())};
  const ComponentJoiningResult r = JoinComponents(scene.input, kept, ComponentJoiningOptions(), &models);
  ASSERT_EQ(models.size(), 1u);
  EXPECT_EQ(models[0].poses.size(), ids.size());
  EXPECT_TRUE(r.joined.empty());
  ASSERT_TRUE(r.not_joined.count(wrong));
  EXPECT_NE(r.not_joined.at(wrong).find("disagrees with its verified pairs"), std::string::npos)
      << r.not_joined.at(wrong);
  ASSERT_TRUE(r.not_joined.count(lonely));
  EXPECT_EQ(r.not_joined.at(lonely), "no verified pair");
}

// The tracks of `scene` cut where they cross between the images below `split` and the rest:
// each track's part on either side becomes a track of its own (parts of one view dropped).
Reconstruction CutTracks(const Reconstruction& tracks, uint32_t split) {
  Reconstruction cut = tracks;
  for (auto& [id, image] : cut.images)
    for (Point2D& p : image.points2D) p.point3D_id = kNoPoint3D;
  cut.points3D.clear();
  for (const auto& [id, point] : tracks.points3D) {
    std::vector<TrackElement> low, high;
    for (const TrackElement& e : point.track) (e.image_id < split ? low : high).push_back(e);
    for (const std::vector<TrackElement>* part : {&low, &high})
      if (part->size() >= 2) cut.AddPoint3D(point.xyz, *part);
  }
  return cut;
}

// PointlessMapper::Solve on an orbit whose tracks are cut in two arcs: two models, each
// through every step and accurate against the truth with its own similarity (measured: 22
// images median 0.061 max 0.095 deg, 18 images median 0.041 max 0.091 deg; 0.5 px noise),
// every image's fate "triplets" in one of them.
TEST(PointlessMapperComponents, TwoArcsGiveTwoAccurateModels) {
  SyntheticOptions so;
  so.scenario = SyntheticScenario::kOrbit;
  so.seed = 3;
  so.num_images = 40;
  so.noise_px = 0.5;
  const SyntheticScene scene = GenerateSyntheticScene(so);
  const uint32_t split = scene.gt.images.begin()->first + 22;
  const Reconstruction tracks = CutTracks(scene.input, split);
  Report report;
  const PointlessMapperResult r = PointlessMapper(PointlessMapperOptions{}).Solve(tracks, &report);
  ASSERT_EQ(r.more_models.size(), 1u);
  const std::vector<const Reconstruction*> models = r.Models();
  EXPECT_EQ(models[0]->images.size(), 22u);
  EXPECT_EQ(models[1]->images.size(), 18u);
  for (const Reconstruction* model : models) {
    const GroundTruthErrors e = CompareToGroundTruth(*model, scene.gt);
    ASSERT_TRUE(e.ok);
    std::printf("model of %zu images: rotation error median %.4f max %.4f deg\n", model->images.size(),
                e.rot_err_deg_median, e.rot_err_deg_max);
    EXPECT_LT(e.rot_err_deg_max, 0.15);
    EXPECT_GT(model->points3D.size(), 100u);
  }
  EXPECT_EQ(report.json()["images_registered"], 40);
  EXPECT_EQ(report.json()["models"].size(), 2u);
  for (const nlohmann::json& fate : report.json()["image_fates"]) {
    EXPECT_EQ(fate["registered_by"], "triplets") << fate.dump();
    const uint32_t id = *tracks.FindImageByName(fate["image"]);
    EXPECT_EQ(fate["model"], id < split ? 0 : 1) << fate.dump();
  }
}

// PointlessMapper::Solve on the planar video (60 views, 0.5 px noise, 2% outliers, seed 7)
// whose initialisation leaves out its first 18 frames (its outlier tests cut the triplet
// component, the larger part is kept): after the global BA most of them join by absolute pose, the model is
// adjusted again with them and stays accurate (measured: 58 of 60 registered, 16 by absolute
// pose, rotation error median 0.21 max 0.42 deg; without them 42 at 0.18 / 0.23 deg); the two
// not joined are named with the reason.
TEST(PointlessMapperComponents, ImagesLeftOutJoinByAbsolutePoseAndTheModelStaysAccurate) {
  SyntheticOptions so;
  so.scenario = SyntheticScenario::kPlanar;
  so.seed = 7;
  so.num_images = 60;
  so.noise_px = 0.5;
  so.outlier_fraction = 0.02;
  const SyntheticScene scene = GenerateSyntheticScene(so);
  Report report;
  const PointlessMapperResult r = PointlessMapper(PointlessMapperOptions{}).Solve(scene.input, &report);
  EXPECT_TRUE(r.more_models.empty());
  EXPECT_GE(r.joining.joined.size(), 10u);
  EXPECT_GE(r.model.images.size(), 55u);
  EXPECT_EQ(r.model.images.size(), r.refined.poses.size());
  for (const auto& [id, registration] : r.joining.joined) EXPECT_TRUE(r.model.images.count(id)) << id;
  const GroundTruthErrors e = CompareToGroundTruth(r.model, scene.gt);
  ASSERT_TRUE(e.ok);
  std::printf("%zu of %zu registered, %zu by absolute pose: relative rotation error median %.4f max %.4f deg "
              "(after a Sim3: median %.4f, centres' collinearity %.3f)\n",
              r.model.images.size(), scene.gt.images.size(), r.joining.joined.size(), e.rel_rot_err_deg_median,
              e.rel_rot_err_deg_max, e.rot_err_deg_median, e.collinearity);
  // Gauge-free errors: the video's centres lie close to a line, so the Sim3 fitted on them
  // leaves a rotation about that line nearly free and its per-image rotation errors carry it.
  // The noise alone (0.5 px) gives about 0.08 deg by the median and 0.3 deg at most; an image
  // joined at a wrong pose shows by degrees.
  EXPECT_LT(e.rel_rot_err_deg_median, 0.1);
  EXPECT_LT(e.rel_rot_err_deg_max, 0.4);
  size_t absolute = 0;
  for (const nlohmann::json& fate : report.json()["image_fates"]) {
    if (fate["model"].is_null()) {
      EXPECT_NE(fate.value("reason", "").find("absolute pose"), std::string::npos) << fate.dump();
    } else {
      absolute += fate["registered_by"] == "absolute_pose";
    }
  }
  EXPECT_EQ(absolute, r.joining.joined.size());
  EXPECT_TRUE(report.json()["stages"].contains("global_ba_before_joining"));
  EXPECT_EQ(report.json()["models"][0]["by_absolute_pose"], r.joining.joined.size());
}

TEST(AlignModels, RecoversTheSimilarityFromSharedPoints) {
  const SyntheticScene scene = Orbit();
  std::map<uint32_t, Pose> a, b;
  for (const auto& [id, image] : scene.gt.images) {
    if (id % 3 != 0) a[id] = image.pose;
    if (id % 3 != 1) b[id] = SomeSimilarity().Apply(image.pose);
  }
  const Reconstruction model_a = TriangulateModel(scene.input, a), model_b = TriangulateModel(scene.input, b);
  const ModelAlignment m = AlignModels(model_a, model_b, ModelAlignmentOptions());
  ASSERT_TRUE(m.success) << m.reason;
  const Sim3 truth = SomeSimilarity().Inverse();
  EXPECT_NEAR(m.b_to_a.s, truth.s, 1e-2 * truth.s);
  // The points' noise (0.5 px, two different sets of views) leaves 0.09 deg (measured; 0 without noise).
  EXPECT_LT(RotationAngleDeg(m.b_to_a.R, truth.R), 0.2);
  EXPECT_GT(m.inliers, 0.9 * m.shared_points);
  // No shared track: no similarity.
  std::map<uint32_t, Pose> c = {{1, scene.gt.images.at(1).pose}};
  const ModelAlignment none = AlignModels(model_a, TriangulateModel(scene.input, c), ModelAlignmentOptions());
  EXPECT_FALSE(none.success);
  EXPECT_EQ(none.shared_points, 0);
}

}  // namespace
}  // namespace pgba
