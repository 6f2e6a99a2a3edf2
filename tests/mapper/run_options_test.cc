// The presets of configs/ are valid `pgba run` configs (every section and key known, every
// value of the right type), and a mistyped key is an error naming the file.
#include "mapper/run_pipeline.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "local_hessian/local_motions.h"
#include "pgba/io/json_config.h"
#include "pgba/util/error.h"

namespace pgba {
namespace {

namespace fs = std::filesystem;

TEST(RunOptions, EveryPresetLoads) {
  const fs::path configs = fs::path(PGBA_SOURCE_DIR) / "configs";
  int n = 0;
  for (const auto& entry : fs::directory_iterator(configs)) {
    if (entry.path().extension() != ".json") continue;
    EXPECT_NO_THROW(LoadRunOptions(entry.path().string())) << entry.path();
    ++n;
  }
  EXPECT_GE(n, 5);  // default, object_ring, aerial, video, longfocal
  const RunOptions video = LoadRunOptions((configs / "video.json").string());
  EXPECT_EQ(video.matching.pairs.method, "sequential");
  const RunOptions longfocal = LoadRunOptions((configs / "longfocal.json").string());
  EXPECT_EQ(longfocal.matching.pairs.method, "sequential");
  EXPECT_EQ(longfocal.reconstruction.refinement.local_motions.kind, MotionKind::kWholeTracks);
}

// What `pgba run` and `reconstruct` run without a config is every options struct's own
// default: no stage struct is overridden on the way (each section compared as the JSON of its
// fields), and an empty config file gives the same.
template <class T>
nlohmann::json Fields(const T& options) {
  return nlohmann::json(options);
}
void ExpectStructDefaults(const RunOptions& o) {
  const PointlessMapperOptions& r = o.reconstruction;
  EXPECT_EQ(Fields(o.features), Fields(FeatureExtractionOptions{}));
  EXPECT_EQ(Fields(o.matching), Fields(MatchingOptions{}));
  EXPECT_EQ(Fields(r.mapper.pairs), Fields(PairOptions{}));
  EXPECT_EQ(Fields(r.mapper.calibration), Fields(ViewGraphCalibrationOptions{}));
  EXPECT_EQ(Fields(r.mapper.triplets), Fields(TripletOptions{}));
  EXPECT_EQ(Fields(r.mapper.global_init), Fields(GlobalInitOptions{}));
  EXPECT_EQ(Fields(r.refinement.local_motions), Fields(LocalMotionOptions{}));
  EXPECT_EQ(Fields(r.refinement.local_hessian), Fields(LocalHessianOptions{}));
  EXPECT_EQ(Fields(r.refinement.global_ba), Fields(GlobalBAOptions{}));
  EXPECT_EQ(Fields(r.refinement.point_based), Fields(PointBasedOptions{}));
  EXPECT_EQ(Fields(r.refinement.intrinsics), Fields(IntrinsicsOptions{}));
  EXPECT_EQ(Fields(r.gcp), Fields(GcpOptions{}));
  EXPECT_EQ(Fields(r.convergence), Fields(ConvergenceOptions{}));
  EXPECT_EQ(Fields(r.verification), Fields(ImageVerificationOptions{}));
}

TEST(RunOptions, WithoutAConfigTheStructDefaultsRun) {
  ExpectStructDefaults(LoadRunOptions(""));
  const fs::path path = fs::temp_directory_path() / "pgba_run_options_empty.json";
  std::ofstream(path) << "{}";
  ExpectStructDefaults(LoadRunOptions(path.string()));
  fs::remove(path);
  // The default method is whole-track motions with the checked re-linearisation, as the
  // structs say, and the paper's preset states the triplet method completely.
  const RunOptions paper = LoadRunOptions((fs::path(PGBA_SOURCE_DIR) / "configs" / "paper_triplets.json").string());
  EXPECT_EQ(paper.reconstruction.refinement.local_motions.kind, MotionKind::kTriplets);
  EXPECT_EQ(Fields(paper.reconstruction.refinement.local_hessian), Fields(PaperTripletLocalHessianOptions()));
  EXPECT_EQ(Fields(paper.reconstruction.refinement.global_ba), Fields(PaperTripletGlobalBAOptions()));
  EXPECT_NE(Fields(LocalHessianOptions{}), Fields(PaperTripletLocalHessianOptions()));
  EXPECT_NE(Fields(GlobalBAOptions{}), Fields(PaperTripletGlobalBAOptions()));
}

TEST(RunOptions, UnknownKeyNamesTheFile) {
  const fs::path path = fs::temp_directory_path() / "pgba_run_options_bad.json";
  std::ofstream(path) << R"({"global_ba": {"max_rounds": 3, "huber_facter": 2}})";
  try {
    LoadRunOptions(path.string());
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("huber_facter"), std::string::npos) << e.what();
  }
  fs::remove(path);
}

// One key under matching.verification.relative_pose overrides that key only: the block's other
// fields keep the front end's verification defaults (1 px, 40 inliers, Sampson scoring, up to 6
// refinement passes until converged; two_view_verification.h), not RelativePoseOptions' generic
// ones (2 px, 15 inliers, OpenGV scoring, 2 fixed passes), and the other blocks are untouched.
TEST(RunOptions, OneRelativePoseKeyKeepsTheOthers) {
  const fs::path path = fs::temp_directory_path() / "pgba_run_options_one_key.json";
  std::ofstream(path) << R"({"matching": {"verification": {"relative_pose": {"seed": 7}}},
                             "pairs": {"relative_pose": {"min_inliers": 33}}})";
  const RunOptions o = LoadRunOptions(path.string());
  fs::remove(path);
  const RelativePoseOptions& v = o.matching.verification.relative_pose;
  EXPECT_EQ(v.seed, 7u);
  EXPECT_EQ(v.threshold_px, 1.0);
  EXPECT_EQ(v.min_inliers, 40);
  EXPECT_EQ(v.scoring, "sampson");
  EXPECT_EQ(v.refine_passes, 6);
  EXPECT_TRUE(v.refine_until_converged);
  EXPECT_EQ(v.algorithm, "stewenius");
  EXPECT_EQ(v.max_iterations, 2000);
  EXPECT_EQ(o.matching.verification.min_inlier_ratio, 0.1);
  EXPECT_EQ(o.matching.verification.max_rotation_sd_deg, 1.0);
  // The tracks' view graph: its own block, generic defaults but the one key given.
  const RelativePoseOptions& p = o.reconstruction.mapper.pairs.relative_pose;
  EXPECT_EQ(p.min_inliers, 33);
  EXPECT_EQ(p.threshold_px, 2.0);
  EXPECT_EQ(p.scoring, "opengv");
  EXPECT_EQ(p.refine_passes, 2);
  EXPECT_FALSE(p.refine_until_converged);
}

// Section "components": the joining and merging keys reach the mapper's options, the others
// keep their defaults.
TEST(RunOptions, ComponentsSectionSetsJoiningAndMerging) {
  const fs::path path = fs::temp_directory_path() / "pgba_run_options_components.json";
  std::ofstream(path) << R"({"components": {"merge_models": false, "min_pose_inliers": 12, "min_correspondences": 15,
                                             "max_merge_direction_deg": 3}})";
  const RunOptions o = LoadRunOptions(path.string());
  fs::remove(path);
  const ComponentJoiningOptions& c = o.reconstruction.components;
  EXPECT_FALSE(c.merge_models);
  EXPECT_TRUE(c.join_images);
  EXPECT_EQ(c.registration.absolute_pose.min_inliers, 12);
  EXPECT_EQ(c.registration.min_correspondences, 15);
  EXPECT_EQ(c.pairs.max_direction_deg, 3.0);
  EXPECT_EQ(c.pairs.min_pairs, 2);
  EXPECT_EQ(c.registration.absolute_pose.threshold_px, 4.0);
}

// Layered presets: a value set before the file is read and not named by it survives, at every
// depth of the nested blocks.
TEST(RunOptions, NestedBlockKeepsPresetValues) {
  const fs::path path = fs::temp_directory_path() / "pgba_run_options_layered.json";
  std::ofstream(path) << R"({"matching": {"verification": {"relative_pose": {"threshold_px": 1.5}}}})";
  const Config config = Config::Load(path.string());
  fs::remove(path);
  MatchingOptions m;
  m.verification.relative_pose.min_inliers = 55;
  m.verification.relative_pose.scoring = "opengv";
  m.verification.min_inlier_ratio = 0.2;
  ReadSection(config, "matching", &m);
  EXPECT_EQ(m.verification.relative_pose.threshold_px, 1.5);
  EXPECT_EQ(m.verification.relative_pose.min_inliers, 55);
  EXPECT_EQ(m.verification.relative_pose.scoring, "opengv");
  EXPECT_EQ(m.verification.relative_pose.refine_passes, 6);
  EXPECT_EQ(m.verification.min_inlier_ratio, 0.2);
}

}  // namespace
}  // namespace pgba
