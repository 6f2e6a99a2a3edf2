// The feature cache carries a checksum: a file damaged in place (same size, one bit
// flipped) is an InputError naming it, as a truncated one is, so that the features stage
// recomputes it instead of matching with silently wrong keypoints or descriptors.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "features/feature_file.h"
#include "pgba/util/error.h"
#include "pgba/util/input_file.h"

namespace pgba {
namespace {
namespace fs = std::filesystem;

FeatureSet SmallFeatureSet() {
  FeatureSet f;
  f.width = 64;
  f.height = 48;
  for (int i = 0; i < 5; ++i) f.keypoints.push_back({1.5f * i, 2.5f * i, 1.f + i, 0.1f * i});
  f.descriptors.create(5, kSiftDescriptorSize, CV_8U);
  for (int i = 0; i < 5; ++i)
    for (int k = 0; k < kSiftDescriptorSize; ++k) f.descriptors.at<uint8_t>(i, k) = static_cast<uint8_t>(i * 7 + k);
  return f;
}

TEST(FeatureFileChecksum, EveryFlippedBitIsDetected) {
  const fs::path dir = fs::temp_directory_path() / ("pgba_featsum_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string path = (dir / "a.bin").string();
  WriteFeatureFile(path, SmallFeatureSet(), "key");
  std::string key;
  const FeatureSet back = ReadFeatureFile(path, &key);
  EXPECT_EQ(key, "key");
  ASSERT_EQ(back.size(), 5u);
  EXPECT_EQ(back.keypoints[3].y, 7.5f);
  EXPECT_EQ(back.descriptors.at<uint8_t>(4, 100), 128);

  const std::string original = ReadRegularFile(path);
  const std::string damaged_path = (dir / "d.bin").string();
  int detected = 0, flips = 0;
  // Every byte once, a different bit each time: the payload (keypoints, descriptors), the
  // header, the trailer and the checksum itself.
  for (size_t i = 0; i < original.size(); ++i, ++flips) {
    std::string damaged = original;
    damaged[i] = static_cast<char>(damaged[i] ^ (1 << (i % 8)));
    std::ofstream(damaged_path, std::ios::binary) << damaged;
    try {
      ReadFeatureFile(damaged_path);
      ADD_FAILURE() << "flipped bit " << i % 8 << " of byte " << i << " was accepted";
    } catch (const InputError& e) {
      ++detected;
      EXPECT_EQ(std::string(e.what()).rfind(damaged_path + ": ", 0), 0u) << e.what();
    }
  }
  EXPECT_EQ(detected, flips);
  // A flip in the descriptors (which no size or header check sees) names the damage.
  std::string damaged = original;
  damaged[original.size() - 100] ^= 0x10;
  std::ofstream(damaged_path, std::ios::binary) << damaged;
  try {
    ReadFeatureFile(damaged_path);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), damaged_path + ": damaged feature file (checksum mismatch)");
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace pgba
