// Fuzz target: the feature cache file (features/feature_file.h): header bounds, truncation,
// trailer and checksum. Most mutations fail the checksum; the seeds include files whose
// checksum is recomputed after the damage (see Seeds), so that the checks behind it are
// reached too.
#include "features/feature_file.h"

#include <cstring>

#include "pgba/util/checksum.h"
#include "pgba/util/input_file.h"
#include "tests/fuzz/fuzz_support.h"

namespace pgba::fuzz {
namespace {

FeatureSet Features(int n) {
  FeatureSet f;
  f.width = 64;
  f.height = 48;
  for (int i = 0; i < n; ++i) f.keypoints.push_back({1.5f * i, 2.5f * i, 1.f + i, 0.1f * i});
  f.descriptors.create(n, kSiftDescriptorSize, CV_8U);
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < kSiftDescriptorSize; ++k) f.descriptors.at<uint8_t>(i, k) = static_cast<uint8_t>(i + k);
  return f;
}

std::string Written(int n, const std::string& key) {
  const std::string path = (ScratchDir() / "seed.bin").string();
  WriteFeatureFile(path, Features(n), key);
  return ReadRegularFile(path);
}

}  // namespace

std::vector<std::string> Seeds() { return {Written(3, "key"), Written(0, ""), Written(1, std::string(300, 'k'))}; }

}  // namespace pgba::fuzz

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace pgba;
  std::string bytes = fuzz::Bytes(data, size);
  // Every other input gets a valid checksum over its (mutated) body, to reach the header,
  // size and trailer checks that a checksum mismatch would otherwise stop first.
  if (bytes.size() >= 8 && (bytes.size() % 2 == 0)) {
    const uint64_t sum = Fnv1a64(bytes.data(), bytes.size() - 8);
    std::memcpy(bytes.data() + bytes.size() - 8, &sum, 8);
  }
  const std::string path = fuzz::WriteScratchFile("features.bin", bytes);
  fuzz::ExpectValueOrInputError(path, [&] {
    std::string key;
    const FeatureSet f = ReadFeatureFile(path, &key);
    fuzz::Require(f.descriptors.rows == static_cast<int>(f.keypoints.size()), "descriptor rows != keypoints");
  });
  return 0;
}
