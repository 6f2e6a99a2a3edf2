// COLMAP text models: exact round trip (bytes and bits) on a random model exercising every
// camera model and the format's corner cases, and the shared fountain_p11 ground truth.
// Malformed and corrupted input: colmap_text_malformed_test.cc.
#include "pgba/io/colmap_text.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "pgba/geometry/rotation.h"
#include "pgba/util/error.h"
#include "tests/io/colmap_text_test_support.h"
#include "tests/support/shared_data.h"

namespace pgba {
namespace {
namespace fs = std::filesystem;
using test::RandomModel;
using test::ExpectIdentical;
using test::kFiles;
using test::ReadBytes;
using test::TempDir;
using test::WriteBytes;

TEST(ColmapText, ExactRoundTrip) {
  std::mt19937 rng(1);
  const Reconstruction rec = RandomModel(rng, 30, 400, 25);
  // The model exercises what it claims to.
  size_t longest = 0;
  for (const auto& [id, p] : rec.points3D) longest = std::max(longest, p.track.size());
  EXPECT_GE(longest, 20u);
  ASSERT_TRUE(rec.images.rbegin()->second.points2D.empty());
  TempDir tmp("roundtrip");
  const fs::path a = tmp.path() / "a", b = tmp.path() / "b";
  WriteColmapText(rec, a.string());
  const Reconstruction back = ReadColmapText(a.string());
  ExpectIdentical(rec, back);
  WriteColmapText(back, b.string());
  for (const char* f : kFiles) EXPECT_EQ(ReadBytes(a / f), ReadBytes(b / f)) << f;
  // The last image's empty POINTS2D line is in the file (the format has two lines per image).
  const std::string images = ReadBytes(a / "images.txt");
  const std::string last_name = rec.images.rbegin()->second.name;
  EXPECT_EQ(images.substr(images.size() - last_name.size() - 2), last_name + "\n\n");
  // Once more from the re-read model, and over an existing directory.
  WriteColmapText(ReadColmapText(b.string()), a.string());
  for (const char* f : kFiles) EXPECT_EQ(ReadBytes(a / f), ReadBytes(b / f)) << f;
  // Without the trailing empty line (a file cut right after the last header) it still reads.
  WriteBytes(b / "images.txt", images.substr(0, images.size() - 1));
  ExpectIdentical(rec, ReadColmapText(b.string()));
  // Windows line ends are accepted.
  std::string crlf;
  for (char c : ReadBytes(a / "points3D.txt")) crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
  WriteBytes(b / "points3D.txt", crlf);
  ExpectIdentical(rec, ReadColmapText(b.string()));
}

// Camera::has_prior_focal_length survives cameras.txt in a comment COLMAP ignores; a marker
// naming a camera the file does not have is an error naming the file and line.
TEST(ColmapText, NoPriorFocalLengthRoundTrip) {
  Reconstruction rec;
  for (uint32_t id : {1u, 2u, 7u}) {
    Camera c;
    c.camera_id = id;
    c.model = CameraModel::kSimpleRadial;
    c.width = 640;
    c.height = 480;
    c.params = {768.0, 320.0, 240.0, 0.0};
    c.has_prior_focal_length = id == 2;
    rec.cameras[id] = c;
  }
  TempDir tmp("no_prior_focal");
  const fs::path path = tmp.path() / "cameras.txt";
  WriteColmapCamerasFile(rec, path.string());
  EXPECT_NE(ReadBytes(path).find("# pgba: no prior focal length: 1 7\n"), std::string::npos) << ReadBytes(path);
  const std::map<uint32_t, Camera> back = ReadColmapCameras(path.string());
  EXPECT_FALSE(back.at(1).has_prior_focal_length);
  EXPECT_TRUE(back.at(2).has_prior_focal_length);
  EXPECT_FALSE(back.at(7).has_prior_focal_length);
  // Every camera with a prior: no marker at all (the file is exactly COLMAP's).
  for (auto& [id, c] : rec.cameras) c.has_prior_focal_length = true;
  WriteColmapCamerasFile(rec, path.string());
  EXPECT_EQ(ReadBytes(path).find("pgba:"), std::string::npos);
  for (const char* bad : {"3", "x", "99999999999", "-1"}) {
    WriteBytes(path, std::string("1 SIMPLE_RADIAL 640 480 768 320 240 0\n# pgba: no prior focal length: 1 ") + bad + "\n");
    try {
      ReadColmapCameras(path.string());
      ADD_FAILURE() << bad;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(path.string() + ":2"), std::string::npos) << e.what();
    }
  }
}

TEST(ColmapText, ReadsSharedFountainGroundTruth) {
  const fs::path gt = fs::path(PGBA_SHARED_DIR) / "datasets" / "fountain_p11" / "gt";
  PGBA_NEED_SHARED_DATA(fs::is_directory(gt), gt.string());
  for (bool points_optional : {false, true}) {
    const Reconstruction rec = ReadColmapText(gt.string(), points_optional);
    EXPECT_EQ(rec.cameras.size(), 1u);
    EXPECT_EQ(rec.images.size(), 11u);
    EXPECT_TRUE(rec.points3D.empty());
    const Camera& cam = rec.cameras.at(1);
    EXPECT_EQ(cam.model, CameraModel::kPinhole);
    EXPECT_EQ(cam.width, 3072);
    EXPECT_EQ(cam.height, 2048);
    EXPECT_EQ(cam.params, std::vector<double>({2759.48, 2764.16, 1520.69, 1006.81}));
    const Image& first = rec.images.at(1);
    EXPECT_EQ(first.name, "0000.jpg");
    EXPECT_EQ(first.pose.q().w(), 0.57188318820727402);
    EXPECT_EQ(first.pose.t().z(), -9.8448352068120002);
    for (const auto& [id, im] : rec.images) {
      EXPECT_TRUE(im.points2D.empty());
      EXPECT_NEAR(im.pose.q().norm(), 1.0, 1e-12);
    }
    EXPECT_EQ(rec.FindImageByName("0010.jpg"), std::optional<uint32_t>(11));
  }
  // The same poses without points3D.txt: optional, or an error naming the file.
  TempDir tmp("fountain");
  for (const char* f : {"cameras.txt", "images.txt"}) fs::copy_file(gt / f, tmp.path() / f);
  EXPECT_EQ(ReadColmapText(tmp.path().string(), true).images.size(), 11u);
  try {
    ReadColmapText(tmp.path().string(), false);
    FAIL() << "missing points3D.txt accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("points3D.txt: file not found"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace pgba
