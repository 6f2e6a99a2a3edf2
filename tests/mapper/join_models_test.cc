// JoinModels (step 10 as a report stage), AdjustedStart, and the report's stages done again
// (repeated_stages.h), on a synthetic orbit and on hand-made reports.
#include <gtest/gtest.h>

#include "mapper/join_models.h"
#include "mapper/repeated_stages.h"
#include "tests/mapper/orbit_models.h"
#include "triplets/pair_estimation.h"

namespace pgba {
namespace {

// The adjusted poses of `model` (as the global BA leaves them: here the model's own).
RefinementResult Refined(const GlobalInitResult& model) {
  RefinementResult r;
  r.poses = model.poses;
  return r;
}

TEST(AdjustedStart, TakesThePosesAndDropsTheTripletsOfImagesLeftOut) {
  GlobalInitResult init;
  init.success = true;
  for (uint32_t id : {1u, 2u, 3u, 4u}) init.poses[id] = Pose();
  LocalMotion kept, dropped;
  kept.image_ids = {1, 2, 3};
  dropped.image_ids = {2, 3, 4};
  init.triplets = {kept, dropped};
  std::map<uint32_t, Pose> adjusted;
  for (uint32_t id : {1u, 2u, 3u}) adjusted[id] = Pose::FromRC(Eigen::Matrix3d::Identity(), Eigen::Vector3d(id, 0, 0));
  const GlobalInitResult start = AdjustedStart(init, adjusted);
  ASSERT_EQ(start.poses.size(), 3u);
  EXPECT_EQ(start.poses.at(2).C(), Eigen::Vector3d(2, 0, 0));
  ASSERT_EQ(start.triplets.size(), 1u);
  EXPECT_EQ(start.triplets[0].image_ids, kept.image_ids);
}

// Two arcs of an orbit that share only verified pairs: JoinModels returns the one merged model
// and records the stage; a single model of every image is left as it is (nothing returned).
TEST(JoinModels, ReturnsTheMergedModelsAndRecordsTheStage) {
  const SyntheticScene scene = test::Orbit();
  const uint32_t split = scene.gt.images.begin()->first + 20;
  const Reconstruction cut = test::CutTracks(scene.input, split);
  PairStats stats;
  const std::vector<TwoViewGeometry> pairs = EstimatePairs(scene.input, PairOptions(), &stats);
  std::vector<uint32_t> low, high, all;
  for (const auto& [id, image] : scene.gt.images) {
    (id < split ? low : high).push_back(id);
    all.push_back(id);
  }
  PointlessMapperResult r;
  r.initial.init = test::ModelOf(scene.gt, low, Sim3());
  r.refined = Refined(r.initial.init);
  ComponentModel more;
  more.init = test::ModelOf(scene.gt, high, test::SomeSimilarity());
  more.refined = Refined(more.init);
  r.more_models.push_back(more);
  Report report;
  ComponentJoiningResult joining;
  const std::vector<GlobalInitResult> models = JoinModels(cut, pairs, ComponentJoiningOptions(), r, &report, &joining);
  ASSERT_EQ(models.size(), 1u);
  EXPECT_EQ(models[0].poses.size(), scene.gt.images.size());
  const nlohmann::json& stage = report.json()["stages"]["components"];
  ASSERT_EQ(stage["merges"].size(), 1u);
  EXPECT_EQ(stage["merges"][0]["by"], "verified_pairs");
  EXPECT_EQ(stage["models"], nlohmann::json::array({scene.gt.images.size()}));

  PointlessMapperResult whole;
  whole.initial.init = test::ModelOf(scene.gt, all, Sim3());
  whole.refined = Refined(whole.initial.init);
  Report unchanged;
  EXPECT_TRUE(JoinModels(cut, pairs, ComponentJoiningOptions(), whole, &unchanged, &joining).empty());
  EXPECT_TRUE(unchanged.json()["stages"].contains("components"));
}

TEST(RepeatedStages, KeepTheFirstRoundUnderASuffix) {
  Report report;
  report["stages"] = {{"global_ba", {{"seconds", 1.0}}},
                      {"verification_before_readjustment", {{"seconds", 2.0}}},
                      {"pairs", {{"seconds", 3.0}}}};
  RenameStages(&report, {"global_ba", "triangulation"}, "_again");
  EXPECT_FALSE(report.json()["stages"].contains("global_ba"));
  EXPECT_EQ(report.json()["stages"]["global_ba_again"]["seconds"], 1.0);
  EXPECT_FALSE(report.json()["stages"].contains("triangulation_again"));
  KeepFirstAdjustmentStages(&report);
  EXPECT_EQ(report.json()["stages"]["verification_before_readjustment_before_joining"]["seconds"], 2.0);
  EXPECT_EQ(report.json()["stages"]["pairs"]["seconds"], 3.0);  // not an adjustment's
}

}  // namespace
}  // namespace pgba
