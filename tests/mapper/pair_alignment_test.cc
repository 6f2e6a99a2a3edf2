// AlignModelsByPairs and JoinComponents on a synthetic orbit (40 images, 0.5 px noise) cut into
// two arcs that share no track, so that only the verified pairs across the cuts (estimated
// from the uncut tracks) connect them: the pairs give the similarity between the arcs' models
// and one model within a tight tolerance of the truth; a pair whose rotation or baseline
// disagrees with the others, or baselines that leave the scale free, merge nothing.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "evaluation/ground_truth.h"
#include "mapper/components.h"
#include "mapper/pair_alignment.h"
#include "pgba/geometry/rotation.h"
#include "pgba/scene/triangulate_model.h"
#include "tests/mapper/orbit_models.h"
#include "triplets/pair_estimation.h"

namespace pgba {
namespace {

using test::CutTracks;
using test::ModelOf;
using test::SomeSimilarity;

struct SplitOrbit {
  SyntheticScene scene;
  uint32_t split = 0;
  Reconstruction cut;                  // no track crosses the split
  std::vector<TwoViewGeometry> pairs;  // estimated on the uncut tracks
  std::vector<uint32_t> low, high;
};

SplitOrbit MakeSplitOrbit() {
  SplitOrbit o;
  o.scene = test::Orbit();
  o.split = o.scene.gt.images.begin()->first + 20;
  o.cut = CutTracks(o.scene.input, o.split);
  PairStats stats;
  o.pairs = EstimatePairs(o.scene.input, PairOptions(), &stats);
  for (const auto& [id, image] : o.scene.gt.images) (id < o.split ? o.low : o.high).push_back(id);
  return o;
}

bool Crosses(const TwoViewGeometry& p, uint32_t split) { return (p.image_id1 < split) != (p.image_id2 < split); }

// The pairs within either arc and those across it for which `keep` holds.
template <class Keep>
std::vector<TwoViewGeometry> WithBridges(const SplitOrbit& o, Keep keep) {
  std::vector<TwoViewGeometry> kept;
  for (const TwoViewGeometry& p : o.pairs)
    if (!Crosses(p, o.split) || keep(p)) kept.push_back(p);
  return kept;
}

bool Is(const TwoViewGeometry& p, uint32_t a, uint32_t b) {
  return (p.image_id1 == a && p.image_id2 == b) || (p.image_id1 == b && p.image_id2 == a);
}

// The pairs of `o` within either arc, and across the cuts those of `bridges` (either order).
std::vector<TwoViewGeometry> WithBridges(const SplitOrbit& o, const std::vector<std::pair<uint32_t, uint32_t>>& bridges) {
  return WithBridges(o, [&](const TwoViewGeometry& p) {
    return std::any_of(bridges.begin(), bridges.end(), [&](const auto& b) { return Is(p, b.first, b.second); });
  });
}

// The rotation error of the similarity found against the true one (degrees) and its scale
// relative to the true one.
double RotationErrorDeg(const ModelAlignment& m) { return RotationAngleDeg(m.b_to_a.R, SomeSimilarity().Inverse().R); }
double RelativeScale(const ModelAlignment& m) { return m.b_to_a.s / SomeSimilarity().Inverse().s; }

// The four pairs across the two cuts (20-21, 20-22 at one, 1-39, 1-40 at the other, measured)
// merge the arcs into one model: the similarity within 0.09 deg and 0.08% of the truth
// (measured), the merged model's rotations within 0.05 deg of the truth after its own Sim3.
TEST(JoinComponents, ArcsThatShareOnlyVerifiedPairsMergeIntoTheTruth) {
  const SplitOrbit o = MakeSplitOrbit();
  int crossing = 0;
  for (const TwoViewGeometry& p : o.pairs) crossing += Crosses(p, o.split);
  ASSERT_GE(crossing, 3);
  std::vector<GlobalInitResult> models = {ModelOf(o.scene.gt, o.low, Sim3()),
                                          ModelOf(o.scene.gt, o.high, SomeSimilarity())};
  const ComponentJoiningResult r = JoinComponents(o.cut, o.pairs, ComponentJoiningOptions(), &models);
  ASSERT_EQ(models.size(), 1u);
  EXPECT_EQ(models[0].poses.size(), o.scene.gt.images.size());
  ASSERT_EQ(r.merges.size(), 1u);
  const ModelAlignment& m = r.merges[0].alignment;
  EXPECT_EQ(m.by, MergeEvidence::kVerifiedPairs);
  EXPECT_EQ(m.shared_points, 0);
  EXPECT_EQ(m.pairs, crossing);
  EXPECT_EQ(m.agreeing_pairs, crossing);
  EXPECT_LT(RotationErrorDeg(m), 0.15);
  EXPECT_NEAR(RelativeScale(m), 1.0, 0.003);
  const GroundTruthErrors e = CompareToGroundTruth(TriangulateModel(o.cut, models[0].poses), o.scene.gt);
  ASSERT_TRUE(e.ok);
  EXPECT_EQ(e.num_common, o.scene.gt.images.size());
  std::printf("merged by %d verified pairs: similarity %.4f deg, scale %.5f; model rotation error max %.4f deg, "
              "centre error max %.2e\n",
              m.agreeing_pairs, RotationErrorDeg(m), RelativeScale(m), e.rot_err_deg_max, e.center_err_rel_max);
  EXPECT_LT(e.rot_err_deg_max, 0.1);
  EXPECT_LT(e.center_err_rel_max, 0.003);
  const nlohmann::json j = r.ToJson(o.cut);
  EXPECT_EQ(j["merges"][0]["by"], "verified_pairs");
  EXPECT_EQ(j["merges"][0]["summary"], "by " + std::to_string(crossing) + " verified pairs");
}

// With merging off (config components.merge_models) the arcs stay two models.
TEST(JoinComponents, MergingOffLeavesTheModelsApart) {
  const SplitOrbit o = MakeSplitOrbit();
  std::vector<GlobalInitResult> models = {ModelOf(o.scene.gt, o.low, Sim3()),
                                          ModelOf(o.scene.gt, o.high, SomeSimilarity())};
  ComponentJoiningOptions options;
  options.merge_models = false;
  const ComponentJoiningResult r = JoinComponents(o.cut, o.pairs, options, &models);
  EXPECT_EQ(models.size(), 2u);
  EXPECT_TRUE(r.merges.empty());
}

// One pair across each cut fixes the similarity (the orbit's centres are not in one plane);
// measured 0.06 deg and 0.07% off.
TEST(AlignModelsByPairs, TwoPairsAcrossTwoCutsFixTheSimilarity) {
  const SplitOrbit o = MakeSplitOrbit();
  const GlobalInitResult a = ModelOf(o.scene.gt, o.low, Sim3()), b = ModelOf(o.scene.gt, o.high, SomeSimilarity());
  const std::vector<TwoViewGeometry> pairs = WithBridges(o, {{o.split - 1, o.split}, {o.high.back(), o.low.front()}});
  const ModelAlignment m = AlignModelsByPairs(o.cut, pairs, a.poses, b.poses, PairAlignmentOptions(), ImageVerificationOptions());
  ASSERT_TRUE(m.success) << m.reason;
  EXPECT_EQ(m.agreeing_pairs, 2);
  EXPECT_LT(RotationErrorDeg(m), 0.15);
  EXPECT_NEAR(RelativeScale(m), 1.0, 0.003);
  // The same pairs the other way round give the inverse.
  const ModelAlignment back =
      AlignModelsByPairs(o.cut, pairs, b.poses, a.poses, PairAlignmentOptions(), ImageVerificationOptions());
  ASSERT_TRUE(back.success) << back.reason;
  EXPECT_LT(RotationAngleDeg(back.b_to_a.R, SomeSimilarity().R), 0.15);
  EXPECT_NEAR(back.b_to_a.s / SomeSimilarity().s, 1.0, 0.003);
}

// A pair whose two-view rotation is 10 deg off: of two pairs one agrees, nothing is merged,
// the models stay as they were and the reason says so.
TEST(JoinComponents, APairThatDisagreesMergesNothing) {
  const SplitOrbit o = MakeSplitOrbit();
  std::vector<TwoViewGeometry> pairs = WithBridges(o, {{o.split - 1, o.split}, {o.high.back(), o.low.front()}});
  for (TwoViewGeometry& p : pairs)
    if (Is(p, o.split - 1, o.split)) p.R_21 = ExpSO3(Eigen::Vector3d(0, 10.0 * M_PI / 180, 0)) * p.R_21;
  std::vector<GlobalInitResult> models = {ModelOf(o.scene.gt, o.low, Sim3()),
                                          ModelOf(o.scene.gt, o.high, SomeSimilarity())};
  const ComponentJoiningResult r = JoinComponents(o.cut, pairs, ComponentJoiningOptions(), &models);
  EXPECT_EQ(models.size(), 2u);
  EXPECT_TRUE(r.merges.empty());
  const ModelAlignment m = AlignModelsByPairs(o.cut, pairs, models[0].poses, models[1].poses, PairAlignmentOptions(),
                                              ImageVerificationOptions());
  EXPECT_FALSE(m.success);
  EXPECT_EQ(m.pairs, 2);
  EXPECT_EQ(m.agreeing_pairs, 1);
  EXPECT_NE(m.reason.find("1 of 2 verified pairs between the models agree on their rotation"), std::string::npos)
      << m.reason;
}

// A pair whose rotation is right but whose baseline points 20 deg away: the other three
// over-determine the similarity and name it.
TEST(AlignModelsByPairs, ABaselineThatDisagreesMergesNothing) {
  const SplitOrbit o = MakeSplitOrbit();
  std::vector<TwoViewGeometry> pairs = o.pairs;
  for (TwoViewGeometry& p : pairs)
    if (Is(p, o.split - 1, o.split)) p.t_21 = ExpSO3(Eigen::Vector3d(0, 0, 20.0 * M_PI / 180)) * p.t_21;
  const GlobalInitResult a = ModelOf(o.scene.gt, o.low, Sim3()), b = ModelOf(o.scene.gt, o.high, SomeSimilarity());
  const ModelAlignment m = AlignModelsByPairs(o.cut, pairs, a.poses, b.poses, PairAlignmentOptions(), ImageVerificationOptions());
  EXPECT_FALSE(m.success);
  EXPECT_GE(m.agreeing_pairs, 3);
  EXPECT_NE(m.reason.find("baseline"), std::string::npos) << m.reason;
}

// Two pairs from one image of model a (20-21, 20-22) fix the rays from one centre only: the
// scale is free and nothing is merged.
TEST(AlignModelsByPairs, PairsFromOneImageLeaveTheScaleFree) {
  const SplitOrbit o = MakeSplitOrbit();
  const std::vector<TwoViewGeometry> pairs = WithBridges(o, {{o.split - 1, o.split}, {o.split - 1, o.split + 1}});
  const GlobalInitResult a = ModelOf(o.scene.gt, o.low, Sim3()), b = ModelOf(o.scene.gt, o.high, SomeSimilarity());
  const ModelAlignment m = AlignModelsByPairs(o.cut, pairs, a.poses, b.poses, PairAlignmentOptions(), ImageVerificationOptions());
  EXPECT_EQ(m.agreeing_pairs, 2);
  EXPECT_FALSE(m.success);
  EXPECT_NE(m.reason.find("do not fix the scale"), std::string::npos) << m.reason;
  EXPECT_LT(m.conditioning, 0.1 * kMinConditioning);
}

}  // namespace
}  // namespace pgba
