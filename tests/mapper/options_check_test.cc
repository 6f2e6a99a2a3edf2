// Check() of every Options struct: each numeric field set just outside its range (the range
// table of io/option_ranges.cc, the truth the config reader already enforces) is refused with
// a message that starts with the field's key; the defaults pass. Then the rules between fields
// and the structs that are no config section.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <regex>

#include "averaging/global_init.h"
#include "benchmark/benchmark.h"
#include "evaluation/evaluation.h"
#include "features/extract_features.h"
#include "features/sift_keypoints.h"
#include "local_hessian/whole_track_motions.h"
#include "mapper/run_pipeline.h"
#include "matching/essential_ransac.h"
#include "matching/guided_matching.h"
#include "pgba/geometry/triangulation.h"
#include "pgba/io/option_ranges.h"
#include "report/svg_plot.h"
#include "synthetic/procedural_texture.h"
#include "synthetic/synthetic_scene.h"

namespace pgba {
namespace {

void ForEachNumber(const nlohmann::json& j, const std::string& path,
                   const std::function<void(const std::string&, const nlohmann::json&)>& f) {
  if (j.is_object()) {
    for (const auto& [k, v] : j.items()) ForEachNumber(v, path.empty() ? k : path + "." + k, f);
  } else if (j.is_number()) {
    f(path, j);
  }
}

// Every ranged numeric field of Options (its JSON under the config path `section`) just out of
// range: Check() must name it.
template <typename Options>
int ExpectEachFieldOutOfRangeRefused(const std::string& section) {
  const nlohmann::json defaults = Options{};
  EXPECT_EQ(Options{}.Check(), "") << section << " defaults";
  int refused = 0;
  ForEachNumber(defaults, "", [&](const std::string& key, const nlohmann::json& value) {
    const std::optional<OptionRange> range = RangeOfOption(section + "." + key);
    if (!range || (!range->has_min && !range->has_max)) return;
    const double bad = range->has_min ? range->min - 1 : range->max + 1;
    nlohmann::json spoilt = defaults;
    spoilt[nlohmann::json::json_pointer("/" + std::regex_replace(key, std::regex("\\."), "/"))] =
        value.is_number_integer() ? nlohmann::json(static_cast<int64_t>(std::floor(bad))) : nlohmann::json(bad);
    const std::string message = spoilt.get<Options>().Check();
    EXPECT_EQ(message.rfind(key + " = ", 0), 0u) << section << "." << key << " = " << bad << ": '" << message << "'";
    EXPECT_NE(message.find("out of range"), std::string::npos) << message;
    ++refused;
  });
  return refused;
}

TEST(OptionsCheck, EveryConfigSectionRefusesEachFieldOutOfItsRange) {
  int n = 0;
  n += ExpectEachFieldOutOfRangeRefused<FeatureExtractionOptions>("features");
  n += ExpectEachFieldOutOfRangeRefused<SiftOptions>("features.sift");
  n += ExpectEachFieldOutOfRangeRefused<SiftDetectionOptions>("SiftDetectionOptions");
  n += ExpectEachFieldOutOfRangeRefused<MatchingOptions>("matching");
  n += ExpectEachFieldOutOfRangeRefused<PairSelectionOptions>("matching.pairs");
  n += ExpectEachFieldOutOfRangeRefused<VladOptions>("matching.pairs.vlad");
  n += ExpectEachFieldOutOfRangeRefused<DescriptorMatchOptions>("matching.descriptors");
  n += ExpectEachFieldOutOfRangeRefused<CascadeHashingOptions>("matching.descriptors.cascade_hashing");
  n += ExpectEachFieldOutOfRangeRefused<VerificationOptions>("matching.verification");
  n += ExpectEachFieldOutOfRangeRefused<GuidedMatchingOptions>("matching.verification.guided");
  n += ExpectEachFieldOutOfRangeRefused<TripletConfirmationOptions>("matching.verification.weak_pairs");
  n += ExpectEachFieldOutOfRangeRefused<TrackBuilderOptions>("matching.tracks");
  n += ExpectEachFieldOutOfRangeRefused<RelativePoseOptions>("pairs.relative_pose");
  n += ExpectEachFieldOutOfRangeRefused<PairOptions>("pairs");
  n += ExpectEachFieldOutOfRangeRefused<FundamentalMatrixOptions>("calibration.fundamental");
  n += ExpectEachFieldOutOfRangeRefused<ViewGraphCalibrationOptions>("calibration");
  n += ExpectEachFieldOutOfRangeRefused<AbsolutePoseOptions>("triplets.absolute_pose");
  n += ExpectEachFieldOutOfRangeRefused<BundleAdjusterOptions>("triplets.bundle_adjuster");
  n += ExpectEachFieldOutOfRangeRefused<TripletOptions>("triplets");
  n += ExpectEachFieldOutOfRangeRefused<PairValidationOptions>("global_init.pair_validation");
  n += ExpectEachFieldOutOfRangeRefused<RelativeRotationOptions>("global_init.rotation.observations");
  n += ExpectEachFieldOutOfRangeRefused<RotationAveragingOptions>("global_init.rotation");
  n += ExpectEachFieldOutOfRangeRefused<TranslationAveragingOptions>("global_init.translation");
  n += ExpectEachFieldOutOfRangeRefused<TrackPositioningOptions>("global_init.track_positioning");
  n += ExpectEachFieldOutOfRangeRefused<OutlierInjectionOptions>("OutlierInjectionOptions");
  n += ExpectEachFieldOutOfRangeRefused<GlobalInitOptions>("global_init");
  n += ExpectEachFieldOutOfRangeRefused<LocalMotionOptions>("local_motions");
  n += ExpectEachFieldOutOfRangeRefused<LocalHessianOptions>("local_hessian");
  n += ExpectEachFieldOutOfRangeRefused<GlobalBAOptions>("global_ba");
  n += ExpectEachFieldOutOfRangeRefused<PointBasedOptions>("point_based");
  n += ExpectEachFieldOutOfRangeRefused<GcpOptions>("gcp");
  n += ExpectEachFieldOutOfRangeRefused<ConvergenceOptions>("convergence");
  n += ExpectEachFieldOutOfRangeRefused<SigmaOptions>("SigmaOptions");
  n += ExpectEachFieldOutOfRangeRefused<GroundTruthOptions>("GroundTruthOptions");
  EXPECT_GT(n, 150);
}

TEST(OptionsCheck, CompositesNameTheSection) {
  RunOptions run;
  EXPECT_EQ(run.Check(), "");
  run.reconstruction.refinement.local_hessian.loss.scale = -1;
  EXPECT_EQ(run.Check(), "local_hessian.huber_px = -1.0 is out of range (> 0)");
  run = RunOptions();
  run.reconstruction.mapper.global_init.rotation.loss.scale = 0;
  EXPECT_EQ(run.Check(), "global_init.rotation.loss_scale_deg = 0.0 is out of range (0, 180]");
  run = RunOptions();
  run.matching.verification.relative_pose.max_iterations = 0;
  EXPECT_EQ(run.Check(), "matching.verification.relative_pose.max_iterations = 0 is out of range (>= 1)");
  BenchmarkOptions bench;
  EXPECT_EQ(bench.Check(), "");
  bench.outlier_sweep = {0.0, 1.5};
  EXPECT_EQ(bench.Check(), "outlier_sweep[] = 1.5 is out of range [0, 1]");
  bench = BenchmarkOptions();
  bench.evaluation.sigma.inlier_px = 0;
  EXPECT_EQ(bench.Check(), "evaluation.sigma.inlier_px = 0.0 is out of range (> 0)");
}

TEST(OptionsCheck, RulesBetweenFieldsAndChoices) {
  GuidedMatchingOptions guided;
  guided.min_inliers = guided.max_inliers + 1;
  EXPECT_EQ(guided.Check(), "min_inliers: must not exceed max_inliers");
  PointBasedOptions point_based;
  point_based.first_pass_loss = "tukey";
  EXPECT_EQ(point_based.Check(), "first_pass_loss = \"tukey\" is not one of: huber, cauchy, trivial");
  point_based = PointBasedOptions();
  point_based.bundle.linear_solver = "cholesky";
  EXPECT_EQ(point_based.Check(),
            "bundle.linear_solver = \"cholesky\" is not one of: auto, dense_schur, sparse_schur, iterative_schur");
  DescriptorMatchOptions descriptors;
  descriptors.method = "brute";
  EXPECT_EQ(descriptors.Check(), "method = \"brute\" is not one of: cascade_hashing, kdtree");
  GlobalBAOptions global_ba;
  global_ba.solver.embedded_similarity_iterations = -1;
  EXPECT_EQ(global_ba.Check(), "embedded_similarity_iterations = -1 is out of range (>= 0)");
  EXPECT_EQ(global_ba.solver.Check(), "embedded_similarity_iterations: must be >= 0");
}

TEST(OptionsCheck, StructsThatAreNoConfigSection) {
  EXPECT_EQ(TriangulationOptions().Check(), "");
  TriangulationOptions triangulation;
  triangulation.outlier_px = 0;
  EXPECT_EQ(triangulation.Check(), "outlier_px = 0.0 is out of range (> 0)");
  synthetic::ProceduralTextureOptions texture;
  EXPECT_EQ(texture.Check(), "");
  texture.max_blob = texture.min_blob / 2;
  EXPECT_EQ(texture.Check(), "max_blob: must be >= min_blob");
  EssentialRansacOptions ransac;
  EXPECT_EQ(ransac.Check(), "");
  ransac.confidence = 1.0;
  EXPECT_EQ(ransac.Check(), "confidence = 1.0 is out of range (0, 1)");
  ransac = EssentialRansacOptions();
  ransac.algorithm = "eight_point";
  EXPECT_EQ(ransac.Check(), "algorithm = \"eight_point\" is not one of: stewenius, nister");
  PlotOptions plot;
  EXPECT_EQ(plot.Check(), "");
  plot.height = 0;
  EXPECT_EQ(plot.Check(), "height = 0 is out of range (>= 1)");
  WholeTrackMotionOptions whole;
  EXPECT_EQ(whole.Check(), "");
  whole.max_views = 1;
  EXPECT_EQ(whole.Check(), "max_views = 1 is out of range (>= 2)");
  SyntheticOptions synthetic;
  EXPECT_EQ(synthetic.Check(), "");
  synthetic.noise_px = -1;
  EXPECT_NE(synthetic.Check(), "");
}

}  // namespace
}  // namespace pgba
