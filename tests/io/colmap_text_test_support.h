// Shared by the COLMAP text tests (colmap_text_test.cc, colmap_text_malformed_test.cc): a
// scratch directory, byte-exact file access, a random model that exercises the format and a
// bit-exact comparison of models.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include "pgba/geometry/rotation.h"
#include "pgba/scene/reconstruction.h"

namespace pgba::test {
namespace fs = std::filesystem;

inline const char* const kFiles[] = {"cameras.txt", "images.txt", "points3D.txt"};

// A fresh directory under the system temp dir (or under /dev/shm with `in_memory`: the fuzz
// test rewrites thousands of small files, which on a loaded disk costs seconds), removed at
// scope exit.
inline fs::path ScratchRoot(bool in_memory) {
  std::error_code ec;
  if (in_memory && fs::is_directory("/dev/shm", ec) && ::access("/dev/shm", W_OK) == 0) return "/dev/shm";
  return fs::temp_directory_path();
}

class TempDir {
 public:
  explicit TempDir(const std::string& tag, bool in_memory = false)
      : path_(ScratchRoot(in_memory) / ("pgba_io_" + tag + "_" + std::to_string(::getpid()))) {
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

inline std::string ReadBytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

inline void WriteBytes(const fs::path& p, const std::string& s) {
  std::error_code ec;
  fs::remove(p, ec);  // a new file: truncating an existing one forces a slow flush on ext4
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out << s;
}

// A random model: every camera model, names with spaces (also doubled), images without
// observations (the last image of the file among them), long tracks, and doubles that stress
// the number formatting (negative zero, subnormal, huge, many digits).
inline Reconstruction RandomModel(std::mt19937& rng, int num_images, int num_points, int max_track) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_int_distribution<int> byte(0, 255);
  Reconstruction rec;
  const CameraModel models[] = {CameraModel::kSimplePinhole, CameraModel::kPinhole, CameraModel::kSimpleRadial,
                                CameraModel::kRadial, CameraModel::kOpenCV};
  for (int m = 0; m < 5; ++m) {
    Camera c;
    c.camera_id = 3 + 2 * m;
    c.model = models[m];
    c.width = 1000 + 17 * m;
    c.height = 700 + 3 * m;
    const bool two_focals = c.model == CameraModel::kPinhole || c.model == CameraModel::kOpenCV;
    // Distortion coefficients of a few percent: larger ones fold the image (not invertible,
    // which the reader refuses); the principal point inside the image (likewise).
    const int first_distortion = two_focals ? 4 : 3;
    for (int k = 0; k < CameraModelNumParams(c.model); ++k)
      c.params.push_back(k == 0 ? 900 + 300 * (u(rng) + 1)
                                : (k >= first_distortion       ? 0.05 * u(rng)
                                   : k >= first_distortion - 2 ? 350 + 300 * u(rng)
                                                               : u(rng)));
    if (two_focals) c.params[1] = 1000 + u(rng);
    rec.cameras[c.camera_id] = c;
  }
  const double special[] = {-0.0, 4.9406564584124654e-324, 2.2250738585072014e-308, 1.7976931348623157e308,
                            -1e-300, 0.1, 1.0 / 3.0, 123456789.123456789};
  for (int i = 0; i < num_images; ++i) {
    Image im;
    im.image_id = 1 + 3 * i + (i % 2);
    im.camera_id = 3 + 2 * (i % 5);
    im.name = i % 3 == 0 ? "img " + std::to_string(i) + " with spaces.jpg"
                         : (i % 3 == 1 ? "dir/sub  dir/" + std::to_string(i) + ".png" : "plain" + std::to_string(i));
    im.pose = Pose::FromRC(RandomRotation(rng), 100.0 * Eigen::Vector3d(u(rng), u(rng), u(rng)));
    // Every third image (and the last one) has no observations.
    const int n_obs = (i % 3 == 2 || i == num_images - 1) ? 0 : 2 * max_track + 5;
    for (int k = 0; k < n_obs; ++k) {
      Point2D p;
      p.xy = Eigen::Vector2d(2000 * (u(rng) + 1), 1000 * (u(rng) + 1));
      if (k < 8) p.xy.x() = special[k];
      im.points2D.push_back(p);
    }
    rec.images[im.image_id] = im;
  }
  // Points: tracks over distinct images with free observations, some very long.
  std::vector<uint32_t> with_obs;
  for (const auto& [id, im] : rec.images)
    if (!im.points2D.empty()) with_obs.push_back(id);
  std::map<uint32_t, size_t> next_free;
  for (int j = 0; j < num_points; ++j) {
    std::vector<uint32_t> ids = with_obs;
    std::shuffle(ids.begin(), ids.end(), rng);
    const size_t len = j % 10 == 0 ? std::min<size_t>(ids.size(), max_track) : 2 + j % 3;
    std::vector<TrackElement> track;
    for (size_t k = 0; k < len && k < ids.size(); ++k) {
      size_t& idx = next_free[ids[k]];
      if (idx >= rec.images[ids[k]].points2D.size()) continue;
      track.push_back({ids[k], static_cast<uint32_t>(idx++)});
    }
    if (track.size() < 2) continue;
    const uint64_t pid = rec.AddPoint3D(50.0 * Eigen::Vector3d(u(rng), u(rng), u(rng)), track);
    Point3D& p = rec.points3D[pid];
    p.color = Eigen::Matrix<uint8_t, 3, 1>(byte(rng), byte(rng), byte(rng));
    p.error = j % 4 == 0 ? -1.0 : std::abs(u(rng));
    if (j < 8) p.xyz.y() = special[j];
  }
  EXPECT_EQ(rec.CheckConsistency(), "");
  return rec;
}

inline bool SameBits(double a, double b) { return std::memcmp(&a, &b, sizeof(double)) == 0; }

// Every field equal, doubles to the bit.
inline void ExpectIdentical(const Reconstruction& a, const Reconstruction& b) {
  ASSERT_EQ(a.cameras.size(), b.cameras.size());
  for (const auto& [id, c] : a.cameras) {
    const Camera& d = b.cameras.at(id);
    EXPECT_EQ(c.camera_id, d.camera_id);
    EXPECT_EQ(c.model, d.model);
    EXPECT_EQ(c.width, d.width);
    EXPECT_EQ(c.height, d.height);
    ASSERT_EQ(c.params.size(), d.params.size());
    for (size_t k = 0; k < c.params.size(); ++k) EXPECT_TRUE(SameBits(c.params[k], d.params[k]));
  }
  ASSERT_EQ(a.images.size(), b.images.size());
  for (const auto& [id, im] : a.images) {
    const Image& jm = b.images.at(id);
    EXPECT_EQ(im.image_id, jm.image_id);
    EXPECT_EQ(im.name, jm.name);
    EXPECT_EQ(im.camera_id, jm.camera_id);
    for (int k = 0; k < 4; ++k) EXPECT_TRUE(SameBits(im.pose.q().coeffs()(k), jm.pose.q().coeffs()(k))) << id;
    for (int k = 0; k < 3; ++k) EXPECT_TRUE(SameBits(im.pose.t()(k), jm.pose.t()(k))) << id;
    ASSERT_EQ(im.points2D.size(), jm.points2D.size());
    for (size_t k = 0; k < im.points2D.size(); ++k) {
      EXPECT_TRUE(SameBits(im.points2D[k].xy.x(), jm.points2D[k].xy.x()));
      EXPECT_TRUE(SameBits(im.points2D[k].xy.y(), jm.points2D[k].xy.y()));
      EXPECT_EQ(im.points2D[k].point3D_id, jm.points2D[k].point3D_id);
    }
  }
  ASSERT_EQ(a.points3D.size(), b.points3D.size());
  for (const auto& [id, p] : a.points3D) {
    const Point3D& q = b.points3D.at(id);
    for (int k = 0; k < 3; ++k) EXPECT_TRUE(SameBits(p.xyz(k), q.xyz(k)));
    EXPECT_EQ(p.color, q.color);
    EXPECT_TRUE(SameBits(p.error, q.error));
    ASSERT_EQ(p.track.size(), q.track.size());
    for (size_t k = 0; k < p.track.size(); ++k) {
      EXPECT_EQ(p.track[k].image_id, q.track[k].image_id);
      EXPECT_EQ(p.track[k].point2D_idx, q.track[k].point2D_idx);
    }
  }
}

}  // namespace pgba::test
