#include "features/feature_file.h"

#include <cstring>
#include <fstream>

#include "pgba/util/atomic_file.h"
#include "pgba/util/error.h"

namespace pgba {
namespace {

constexpr char kMagic[8] = {'P', 'G', 'B', 'A', 'F', 'E', 'A', 'T'};
constexpr char kEnd[4] = {'E', 'N', 'D', '.'};
// Sanity bounds that reject garbage headers before allocating.
constexpr uint32_t kMaxKeyLength = 1 << 16;
constexpr uint32_t kMaxKeypoints = 1 << 24;

template <typename T>
void Put(std::ostream& out, const T& v) {
  out.write(reinterpret_cast<const char*>(&v), sizeof(T));
}

template <typename T>
void Get(std::istream& in, T* v, const std::string& path) {
  if (!in.read(reinterpret_cast<char*>(v), sizeof(T))) ThrowInputError(path, 0, "truncated feature file");
}

}  // namespace

void WriteFeatureFile(const std::string& path, const FeatureSet& f, const std::string& key) {
  CV_Assert(f.descriptors.rows == static_cast<int>(f.keypoints.size()));
  CV_Assert(f.keypoints.empty() || (f.descriptors.type() == CV_8U && f.descriptors.isContinuous()));
  WriteFileAtomically(path, [&](std::ostream& out) {
    out.write(kMagic, sizeof(kMagic));
    Put(out, kFeatureFileVersion);
    Put(out, static_cast<uint32_t>(key.size()));
    out.write(key.data(), static_cast<std::streamsize>(key.size()));
    Put(out, static_cast<int32_t>(f.width));
    Put(out, static_cast<int32_t>(f.height));
    Put(out, static_cast<uint32_t>(f.keypoints.size()));
    Put(out, static_cast<uint32_t>(kSiftDescriptorSize));
    static_assert(sizeof(Keypoint) == 4 * sizeof(float), "Keypoint must be 4 packed floats");
    out.write(reinterpret_cast<const char*>(f.keypoints.data()),
              static_cast<std::streamsize>(f.keypoints.size() * sizeof(Keypoint)));
    if (!f.keypoints.empty())
      out.write(reinterpret_cast<const char*>(f.descriptors.data),
                static_cast<std::streamsize>(f.keypoints.size() * kSiftDescriptorSize));
    out.write(kEnd, sizeof(kEnd));
  });
}

FeatureSet ReadFeatureFile(const std::string& path, std::string* key) {
  std::ifstream in(path, std::ios::binary);
  if (!in) ThrowInputError(path, 0, "cannot open feature file");
  char magic[8];
  if (!in.read(magic, sizeof(magic)) || std::memcmp(magic, kMagic, sizeof(magic)) != 0)
    ThrowInputError(path, 0, "not a pgba feature file (bad magic)");
  uint32_t version = 0, key_len = 0;
  Get(in, &version, path);
  if (version != kFeatureFileVersion)
    ThrowInputError(
        path, 0,
        "feature file version " + std::to_string(version) + ", expected " + std::to_string(kFeatureFileVersion));
  Get(in, &key_len, path);
  if (key_len > kMaxKeyLength) ThrowInputError(path, 0, "corrupt feature file header");
  std::string stored_key(key_len, '\0');
  if (!in.read(stored_key.data(), key_len)) ThrowInputError(path, 0, "truncated feature file");
  int32_t width = 0, height = 0;
  uint32_t n = 0, dim = 0;
  Get(in, &width, path);
  Get(in, &height, path);
  Get(in, &n, path);
  Get(in, &dim, path);
  if (width <= 0 || height <= 0 || n > kMaxKeypoints || dim != static_cast<uint32_t>(kSiftDescriptorSize))
    ThrowInputError(path, 0, "corrupt feature file header");
  FeatureSet f;
  f.width = width;
  f.height = height;
  f.keypoints.resize(n);
  f.descriptors.create(static_cast<int>(n), kSiftDescriptorSize, CV_8U);
  if (!in.read(reinterpret_cast<char*>(f.keypoints.data()), static_cast<std::streamsize>(n * sizeof(Keypoint))) ||
      (n > 0 && !in.read(reinterpret_cast<char*>(f.descriptors.data), static_cast<std::streamsize>(n) * dim)))
    ThrowInputError(path, 0, "truncated feature file");
  char end[4];
  if (!in.read(end, sizeof(end)) || std::memcmp(end, kEnd, sizeof(end)) != 0 || in.peek() != EOF)
    ThrowInputError(path, 0, "corrupt feature file (bad trailer)");
  if (key) *key = std::move(stored_key);
  return f;
}

}  // namespace pgba
