// Hostile caches: the feature and tracks caches are keyed on content (the photos' bytes), so
// a damaged or replaced input is never answered from the cache.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "tests/apps/hostile_cli_fixture.h"

namespace {
namespace fs = std::filesystem;
using pgba::test::Bytes;
using pgba::test::Lines;

class HostileCachesCli : public pgba::test::HostileCli {};

// A bit-flipped feature cache file is not used (a silent wrong answer): the run goes on, a
// warning names the file and its features are recomputed (same bytes as the first run).
TEST_F(HostileCachesCli, BitFlippedFeatureCacheIsRecomputedWithAWarning) {
  const fs::path images = Photos("flip_images"), ws = dir_ / "flip_ws";
  const std::string args = "features --images " + images.string() + " --out " + ws.string();
  ASSERT_EQ(Run(args).code, 0);
  const fs::path cache = ws / "features" / "im1.jpg.bin";
  const std::string good = Bytes(cache);
  ASSERT_GT(good.size(), 200u);
  std::string flipped = good;
  flipped[good.size() / 2] ^= 0x10;
  std::ofstream(cache, std::ios::binary | std::ios::trunc) << flipped;
  const pgba::test::CliResult r = Run(args);
  EXPECT_EQ(r.code, 0) << r.output;
  const std::vector<std::string> lines = Lines(r.output);
  ASSERT_EQ(lines.size(), 1u) << r.output;
  EXPECT_EQ(lines[0].rfind("warning: ", 0), 0u) << lines[0];
  EXPECT_NE(lines[0].find(cache.string()), std::string::npos) << lines[0];
  EXPECT_NE(lines[0].find("checksum"), std::string::npos) << lines[0];
  EXPECT_TRUE(Bytes(cache) == good);
}

// Caches keyed on content: a photo replaced by another of the same size with the same
// modification time (cp -p) gets its features computed again, not the cached ones.
TEST_F(HostileCachesCli, FeatureCacheIsKeyedOnThePhotosBytes) {
  const fs::path images = Photos("cache_src");
  const fs::path ws = dir_ / "cache_ws";
  const std::string args = "features --images " + images.string() + " --out " + ws.string();
  ASSERT_EQ(Run(args).code, 0);
  // The larger photo replaced by the smaller one padded to its size (bytes after the JPEG's
  // end are ignored by the decoder): same size, same modification time, another picture.
  fs::path big = images / "im0.jpg", small = images / "im1.jpg";
  if (fs::file_size(big) < fs::file_size(small)) std::swap(big, small);
  const std::string cache = (ws / "features" / (big.filename().string() + ".bin")).string();
  const std::string before = Bytes(cache);
  const auto time = fs::last_write_time(big);
  std::string replacement = Bytes(small);
  replacement.resize(fs::file_size(big), '\0');
  std::ofstream(big, std::ios::binary | std::ios::trunc) << replacement;
  fs::last_write_time(big, time);
  ASSERT_EQ(Run(args).code, 0);
  EXPECT_NE(Bytes(cache), before);
}

// The tracks cache is keyed on the feature files' checksums, which hold the photos' hashes:
// two photos swapped under their names (each image capped at the same feature count, so that
// names and feature counts alone would match) get their tracks computed again.
TEST_F(HostileCachesCli, TracksCacheIsKeyedOnThePhotosContent) {
  const fs::path images = Photos("tracks_cache_src"), out = dir_ / "tracks_cache_out";
  const fs::path config = dir_ / "tracks_cache.json";
  std::ofstream(config) << R"({"features": {"sift": {"max_features": 40}}})";
  const std::string args = "run --images " + images.string() + " --out " + out.string() + " --config " +
                           config.string();
  auto match_cached = [&] {
    const std::string report = Bytes(out / "report.json");
    const size_t match = report.find("\"match\"");
    if (match == std::string::npos) return "no match stage: " + report;
    const size_t cached = report.find("\"cached\"", match);
    return report.substr(cached, report.find_first_of(",\n}", cached) - cached);
  };
  // Unrelated noise photos: the run ends at "no verified matches", after the match stage.
  EXPECT_EQ(Run(args).code, 2);
  ASSERT_TRUE(fs::exists(out / "tracks" / "key.json"));
  EXPECT_EQ(Run(args).code, 2);
  EXPECT_EQ(match_cached(), "\"cached\": true");
  const fs::path a = images / "im0.jpg", b = images / "im1.jpg", tmp = dir_ / "tracks_cache_swap.jpg";
  fs::rename(a, tmp);
  fs::rename(b, a);
  fs::rename(tmp, b);
  EXPECT_EQ(Run(args).code, 2);
  EXPECT_EQ(match_cached(), "\"cached\": false");
}

}  // namespace
