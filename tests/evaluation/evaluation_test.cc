// The evaluation stage end to end: Evaluate on a model, JSON keys, table.
#include <gtest/gtest.h>

#include <sstream>

#include "evaluation/evaluation.h"
#include "tests/evaluation/test_scene.h"

namespace pgba {
namespace {

const std::vector<std::string> kAllKeys = {"images_input",          "images_registered",  "sigma_rms",
                                           "sigma_median",          "inlier_fraction",    "rot_err_deg_median",
                                           "rot_err_deg_max",       "center_err_rel_median", "center_err_rel_max",
                                           "loop_err_rms",          "loop_err_median"};

TEST(Evaluate, TruePosesUpToSimilarity) {
  const test::TestScene s = test::MakeTestScene(41, 12, 2000, 0.5, 300);
  Sim3 S;
  S.s = 3.0;
  S.R = ExpSO3(Eigen::Vector3d(0.3, -1.0, 0.2));
  S.t = Eigen::Vector3d(1, 2, 3);
  Reconstruction model = test::RenumberedPosesOnly(s.gt, 1000);
  for (auto& [id, im] : model.images) im.pose = S.Apply(im.pose);
  const EvaluationMetrics on_truth = Evaluate(s.gt, s.gt, &s.gt, &s.loops);
  const EvaluationMetrics m = Evaluate(model, s.gt, &s.gt, &s.loops);
  EXPECT_EQ(m.images_input, 12u);
  EXPECT_EQ(m.images_registered, 12u);
  // sigma does not depend on the frame (triangulation is similarity-invariant).
  EXPECT_NEAR(m.sigma.rms, on_truth.sigma.rms, 1e-6);
  EXPECT_NEAR(m.loop->rms, on_truth.loop->rms, 1e-6);
  ASSERT_TRUE(m.ground_truth && m.ground_truth->ok);
  EXPECT_LT(m.ground_truth->rot_err_deg_max, 1e-6);
  EXPECT_LT(m.ground_truth->center_err_rel_max, 1e-12);

  const nlohmann::json j = m.ToJson();
  for (const std::string& key : kAllKeys) {
    ASSERT_TRUE(j.contains(key)) << key;
    EXPECT_TRUE(j[key].is_number()) << key;
  }
  EXPECT_EQ(j["images_registered"].get<int>(), 12);
  EXPECT_DOUBLE_EQ(j["sigma_rms"].get<double>(), m.sigma.rms);
  EXPECT_DOUBLE_EQ(j["loop_err_median"].get<double>(), m.loop->median);

  std::ostringstream table;
  m.PrintTable(table);
  EXPECT_NE(table.str().find("sigma rms (px)"), std::string::npos);
  EXPECT_NE(table.str().find("12 / 12"), std::string::npos);
}

TEST(Evaluate, KeysAbsentWhereNotComputable) {
  const test::TestScene s = test::MakeTestScene(42, 8, 300);
  Reconstruction model = test::RenumberedPosesOnly(s.gt, 0);
  const nlohmann::json j = Evaluate(model, s.gt, nullptr, nullptr).ToJson();
  for (const char* key : {"rot_err_deg_median", "rot_err_deg_max", "center_err_rel_median", "center_err_rel_max",
                          "loop_err_rms", "loop_err_median"})
    EXPECT_FALSE(j.contains(key)) << key;
  EXPECT_TRUE(j.contains("sigma_rms"));

  // No common image: nothing but the counts.
  Reconstruction other = model;
  for (auto& [id, im] : other.images) im.name = "other_" + im.name;
  const EvaluationMetrics none = Evaluate(other, s.gt, &s.gt, &s.loops);
  const nlohmann::json k = none.ToJson();
  EXPECT_EQ(k["images_input"].get<int>(), 8);
  EXPECT_EQ(k["images_registered"].get<int>(), 0);
  for (const std::string& key : kAllKeys)
    if (key != "images_input" && key != "images_registered") {
      EXPECT_FALSE(k.contains(key)) << key;
    }
  std::ostringstream table;
  none.PrintTable(table);
  EXPECT_NE(table.str().find("n/a"), std::string::npos);
}

TEST(Evaluate, OptionsAreJsonLoadable) {
  const nlohmann::json j = nlohmann::json::parse(R"({"sigma": {"inlier_px": 2.5}, "ground_truth": {"max_rounds": 1}})");
  const EvaluationOptions o = j.get<EvaluationOptions>();
  EXPECT_EQ(o.sigma.inlier_px, 2.5);
  EXPECT_EQ(o.sigma.huber_px, SigmaOptions{}.huber_px);  // defaults kept
  EXPECT_EQ(o.ground_truth.max_rounds, 1);
  EXPECT_EQ(o.ground_truth.outlier_factor, 5.0);
}

}  // namespace
}  // namespace pgba
