// The presets of configs/ are valid `pgba run` configs (every section and key known, every
// value of the right type), and a mistyped key is an error naming the file.
#include "mapper/run_pipeline.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

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
  EXPECT_EQ(longfocal.reconstruction.refinement.local_motions.views, 7);
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

}  // namespace
}  // namespace pgba
