#include "features/feature_file.h"

#include <algorithm>
#include <cstring>
#include <fstream>

#include "pgba/util/atomic_file.h"
#include "pgba/util/checksum.h"
#include "pgba/util/error.h"
#include "pgba/util/input_file.h"

namespace pgba {
namespace {

constexpr char kMagic[8] = {'P', 'G', 'B', 'A', 'F', 'E', 'A', 'T'};
constexpr char kEnd[4] = {'E', 'N', 'D', '.'};
// Sanity bounds that reject garbage headers before allocating.
constexpr uint32_t kMaxKeyLength = 1 << 16;
constexpr uint32_t kMaxKeypoints = 1 << 24;

template <typename T>
void Put(std::string* out, const T& v) {
  out->append(reinterpret_cast<const char*>(&v), sizeof(T));
}

// Reads the file's bytes in order; running past the end is "truncated".
class Cursor {
 public:
  Cursor(const std::string& bytes, const std::string& path) : bytes_(bytes), path_(path) {}
  void Read(void* out, size_t n) {
    if (n == 0) return;  // `out` may be the null data() of an empty vector (memcpy's UB)
    if (n > bytes_.size() - pos_) ThrowInputError(path_, 0, "truncated feature file");
    std::memcpy(out, bytes_.data() + pos_, n);
    pos_ += n;
  }
  template <typename T>
  T Get() {
    T v;
    Read(&v, sizeof(T));
    return v;
  }
  size_t pos() const { return pos_; }

 private:
  const std::string& bytes_;
  const std::string& path_;
  size_t pos_ = 0;
};

}  // namespace

void WriteFeatureFile(const std::string& path, const FeatureSet& f, const std::string& key) {
  CV_Assert(f.descriptors.rows == static_cast<int>(f.keypoints.size()));
  CV_Assert(f.keypoints.empty() || (f.descriptors.type() == CV_8U && f.descriptors.isContinuous()));
  std::string bytes(kMagic, sizeof(kMagic));
  Put(&bytes, kFeatureFileVersion);
  Put(&bytes, static_cast<uint32_t>(key.size()));
  bytes += key;
  Put(&bytes, static_cast<int32_t>(f.width));
  Put(&bytes, static_cast<int32_t>(f.height));
  Put(&bytes, f.contrast_threshold);
  Put(&bytes, static_cast<uint32_t>(f.keypoints.size()));
  Put(&bytes, static_cast<uint32_t>(kSiftDescriptorSize));
  static_assert(sizeof(Keypoint) == 4 * sizeof(float), "Keypoint must be 4 packed floats");
  bytes.append(reinterpret_cast<const char*>(f.keypoints.data()), f.keypoints.size() * sizeof(Keypoint));
  if (!f.keypoints.empty())
    bytes.append(reinterpret_cast<const char*>(f.descriptors.data), f.keypoints.size() * kSiftDescriptorSize);
  bytes.append(kEnd, sizeof(kEnd));
  Put(&bytes, Fnv1a64(bytes));
  WriteStringAtomically(path, bytes);
}

uint64_t FeatureFileChecksum(const std::string& path) {
  RequireRegularFile(path);
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  uint64_t sum = 0;
  const std::streamoff size = in ? static_cast<std::streamoff>(in.tellg()) : -1;
  if (size < static_cast<std::streamoff>(sizeof(kMagic) + sizeof(kEnd) + sizeof(sum)))
    ThrowInputError(path, 0, "truncated feature file");
  in.seekg(size - static_cast<std::streamoff>(sizeof(sum)));
  if (!in.read(reinterpret_cast<char*>(&sum), sizeof(sum))) ThrowInputError(path, 0, "read error");
  return sum;
}

FeatureSet ReadFeatureFile(const std::string& path, std::string* key) {
  const std::string bytes = ReadRegularFile(path);
  Cursor in(bytes, path);
  if (bytes.size() < sizeof(kMagic) || std::memcmp(bytes.data(), kMagic, sizeof(kMagic)) != 0)
    ThrowInputError(path, 0, "not a pgba feature file (bad magic)");
  char magic[sizeof(kMagic)];
  in.Read(magic, sizeof(magic));
  const uint32_t version = in.Get<uint32_t>();
  if (version != kFeatureFileVersion)
    ThrowInputError(
        path, 0,
        "feature file version " + std::to_string(version) + ", expected " + std::to_string(kFeatureFileVersion));
  // The checksum first: every later check may then trust the bytes it reads.
  uint64_t stored_sum = 0;
  if (bytes.size() < sizeof(kMagic) + sizeof(kEnd) + sizeof(stored_sum)) ThrowInputError(path, 0, "truncated feature file");
  const size_t body = bytes.size() - sizeof(stored_sum);
  std::memcpy(&stored_sum, bytes.data() + body, sizeof(stored_sum));
  if (Fnv1a64(bytes.data(), body) != stored_sum)
    ThrowInputError(path, 0, "damaged feature file (checksum mismatch)");
  const uint32_t key_len = in.Get<uint32_t>();
  if (key_len > kMaxKeyLength) ThrowInputError(path, 0, "corrupt feature file header");
  std::string stored_key(key_len, '\0');
  in.Read(stored_key.data(), key_len);
  const int32_t width = in.Get<int32_t>(), height = in.Get<int32_t>();
  const float contrast_threshold = in.Get<float>();
  const uint32_t n = in.Get<uint32_t>(), dim = in.Get<uint32_t>();
  if (width <= 0 || height <= 0 || !(contrast_threshold >= 0.f) || n > kMaxKeypoints || dim != static_cast<uint32_t>(kSiftDescriptorSize))
    ThrowInputError(path, 0, "corrupt feature file header");
  // Before allocating n keypoints: the rest of the body must hold exactly them and the trailer.
  if (static_cast<uint64_t>(n) * (sizeof(Keypoint) + dim) + sizeof(kEnd) != body - std::min(body, in.pos()))
    ThrowInputError(path, 0, "corrupt feature file (size does not match its header)");
  FeatureSet f;
  f.width = width;
  f.height = height;
  f.contrast_threshold = contrast_threshold;
  f.keypoints.resize(n);
  f.descriptors.create(static_cast<int>(n), kSiftDescriptorSize, CV_8U);
  in.Read(f.keypoints.data(), n * sizeof(Keypoint));
  if (n > 0) in.Read(f.descriptors.data, static_cast<size_t>(n) * dim);
  char end[4];
  in.Read(end, sizeof(end));
  if (std::memcmp(end, kEnd, sizeof(end)) != 0 || in.pos() != body)
    ThrowInputError(path, 0, "corrupt feature file (bad trailer)");
  if (key) *key = std::move(stored_key);
  return f;
}

}  // namespace pgba
