// Every numeric option has a valid range, checked when a config is read: a value outside it
// is an InputError naming the file, the key, the value and the range.
#include "pgba/io/option_ranges.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <functional>

#include "mapper/run_pipeline.h"
#include "pgba/util/error.h"

namespace pgba {
namespace {
namespace fs = std::filesystem;

// The defaults of every section a command accepts (LoadRunOptions' schema).
nlohmann::json DefaultSections() {
  const RunOptions o;
  const PointlessMapperOptions& r = o.reconstruction;
  return {{"features", o.features},
          {"matching", o.matching},
          {"pairs", r.mapper.pairs},
          {"triplets", r.mapper.triplets},
          {"global_init", r.mapper.global_init},
          {"local_motions", r.refinement.local_motions},
          {"local_hessian", r.refinement.local_hessian},
          {"global_ba", r.refinement.global_ba},
          {"point_based", r.refinement.point_based},
          {"gcp", r.gcp},
          {"components", r.components}};
}

void ForEachNumber(const nlohmann::json& j, const std::string& path,
                   const std::function<void(const std::string&, double)>& f) {
  if (j.is_object()) {
    for (const auto& [k, v] : j.items()) ForEachNumber(v, path.empty() ? k : path + "." + k, f);
  } else if (j.is_array()) {
    for (const auto& v : j) ForEachNumber(v, path + "[]", f);
  } else if (j.is_number()) {
    f(path, j.get<double>());
  }
}

// The guard that keeps the table complete: an option added to an Options struct without a
// range in option_ranges.cc fails here, by name.
TEST(OptionRanges, EveryNumericOptionHasARangeThatHoldsItsDefault) {
  int count = 0;
  ForEachNumber(DefaultSections(), "", [&](const std::string& key, double value) {
    ++count;
    const std::optional<OptionRange> range = RangeOfOption(key);
    ASSERT_TRUE(range.has_value()) << key << " has no range in src/pgba/io/option_ranges.cc";
    EXPECT_TRUE(range->Contains(value)) << key << " = " << value << " default outside " << range->Describe();
  });
  EXPECT_GT(count, 100);
}

class OptionRangesConfig : public ::testing::Test {
 protected:
  void SetUp() override {
    path_ = fs::temp_directory_path() / ("pgba_ranges_" + std::to_string(::getpid()) + ".json");
  }
  void TearDown() override { fs::remove(path_); }
  std::string ErrorOf(const std::string& config) {
    std::ofstream(path_) << config;
    try {
      LoadRunOptions(path_.string());
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  }
  fs::path path_;
};

TEST_F(OptionRangesConfig, ReportedCasesNameTheKeyAndTheRange) {
  EXPECT_EQ(ErrorOf(R"({"local_hessian": {"huber_px": -1}})"),
            path_.string() + ": local_hessian.huber_px = -1 is out of range (> 0)");
  EXPECT_EQ(ErrorOf(R"({"triplets": {"outlier_threshold_px": 0}})"),
            path_.string() + ": triplets.outlier_threshold_px = 0 is out of range (> 0)");
  EXPECT_EQ(ErrorOf(R"({"matching": {"verification": {"relative_pose": {"confidence": 1.0}}}})"),
            path_.string() + ": matching.verification.relative_pose.confidence = 1.0 is out of range (0, 1)");
  EXPECT_EQ(ErrorOf(R"({"pairs": {"min_inlier_ratio": 1.5}})"),
            path_.string() + ": pairs.min_inlier_ratio = 1.5 is out of range [0, 1]");
  EXPECT_EQ(ErrorOf(R"({"local_motions": {"neighbour_strides": [1, 0]}})"),
            path_.string() + ": local_motions.neighbour_strides[] = 0 is out of range (>= 1)");
  EXPECT_EQ(ErrorOf(R"({"point_based": {"bundle": {"max_iterations": 0}}})"),
            path_.string() + ": point_based.bundle.max_iterations = 0 is out of range (>= 1)");
  EXPECT_EQ(ErrorOf(R"({"components": {"min_merge_pairs": 1}})"),
            path_.string() + ": components.min_merge_pairs = 1 is out of range (>= 2)");
  EXPECT_EQ(ErrorOf(R"({"components": {"max_merge_rotation_deg": 0}})"),
            path_.string() + ": components.max_merge_rotation_deg = 0 is out of range (0, 180]");
  // A rule between two keys.
  EXPECT_EQ(ErrorOf(R"({"components": {"min_pose_inliers": 30}})"),
            path_.string() + ": components.min_pose_inliers = 30 exceeds min_correspondences = 20");
}

TEST_F(OptionRangesConfig, MethodNamesAreOneOfTheirChoices) {
  EXPECT_EQ(ErrorOf(R"({"matching": {"verification": {"relative_pose": {"scoring": "samspon"}}}})"),
            path_.string() + ": matching.verification.relative_pose.scoring = \"samspon\" is not one of: sampson, opengv");
  EXPECT_EQ(ErrorOf(R"({"pairs": {"relative_pose": {"algorithm": "8point"}}})"),
            path_.string() + ": pairs.relative_pose.algorithm = \"8point\" is not one of: stewenius, nister");
  EXPECT_EQ(ErrorOf(R"({"pairs": {"relative_pose": {"scoring": "opengv", "algorithm": "nister"}}})"), "");
}

TEST_F(OptionRangesConfig, BoundsThemselvesAndDocumentedOffValuesAreAccepted) {
  EXPECT_EQ(ErrorOf(R"({"pairs": {"min_inlier_ratio": 1}, "matching": {"tracks": {"min_track_length": 2}}})"), "");
  EXPECT_EQ(ErrorOf(R"({"global_ba": {"irls_factor": 0, "huber_factor": -1}, "local_hessian": {"attenuation_q": 0}})"),
            "");
  EXPECT_EQ(ErrorOf(R"({"point_based": {"filter_max_error_px": 0}, "features": {"sift": {"max_image_size": 0}}})"), "");
}

TEST(OptionRanges, EveryPresetIsInRange) {
  for (const auto& entry : fs::directory_iterator(fs::path(PGBA_SOURCE_DIR) / "configs"))
    EXPECT_NO_THROW(LoadRunOptions(entry.path().string())) << entry.path();
}

}  // namespace
}  // namespace pgba
