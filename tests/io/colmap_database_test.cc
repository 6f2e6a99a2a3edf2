// COLMAP database import against a database written with COLMAP's schema
// (tests/support/colmap_database_writer.h), so the expected content is known exactly.
#include "pgba/io/colmap_database.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <random>
#include <set>

#include "pgba/util/error.h"
#include "tests/support/colmap_database_writer.h"

namespace pgba {
namespace {
namespace fs = std::filesystem;

using test::DbWriter;

std::string TempPath(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("pgba_colmap_db_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return (dir / name).string();
}

// Three images of 5 keypoints each; keypoint k of image i sits at (100 i + k + 0.25, 7 k).
std::vector<float> KeypointBlob(int i, int cols) {
  std::vector<float> d;
  for (int k = 0; k < 5; ++k) {
    d.push_back(100.f * i + k + 0.25f);
    d.push_back(7.f * k);
    for (int c = 2; c < cols; ++c) d.push_back(-1.f);  // affine shape columns, ignored
  }
  return d;
}

TEST(ColmapDatabase, ImportMatchesWhatWasWritten) {
  const std::string path = TempPath("ok.db");
  {
    DbWriter w(path);
    w.Camera(1, 1, 640, 480, {500, 510, 320, 240});   // PINHOLE
    w.Camera(2, 2, 800, 600, {600, 400, 300, 0.01});  // SIMPLE_RADIAL
    w.Image(1, "a.jpg", 1);
    w.Image(2, "b.jpg", 1);
    w.Image(5, "c.jpg", 2);
    w.Keypoints(1, 5, 6, KeypointBlob(1, 6));
    w.Keypoints(2, 5, 2, KeypointBlob(2, 2));
    w.Keypoints(5, 5, 4, KeypointBlob(5, 4));
    // Tracks: X = a0 b1 c2 (seen by all three pairs), Y = a3 b3, Z = b4 c4.
    w.TwoView(1, 2, {{0, 1}, {3, 3}}, 2);
    w.TwoView(2, 5, {{1, 2}, {4, 4}}, 3);
    w.TwoView(1, 5, {{0, 2}}, 4);
  }
  ColmapDatabase db = ReadColmapDatabase(path);
  ASSERT_EQ(db.cameras.size(), 2u);
  EXPECT_EQ(db.cameras.at(1).model, CameraModel::kPinhole);
  EXPECT_EQ(db.cameras.at(2).model, CameraModel::kSimpleRadial);
  EXPECT_EQ(db.cameras.at(2).params, (std::vector<double>{600, 400, 300, 0.01}));
  EXPECT_EQ(db.cameras.at(1).width, 640);
  ASSERT_EQ(db.images.size(), 3u);
  EXPECT_EQ(db.images[2].image_id, 5u);
  EXPECT_EQ(db.images[2].name, "c.jpg");
  EXPECT_EQ(db.images[2].camera_id, 2u);
  for (const KeypointImage& im : db.images) {
    ASSERT_EQ(im.keypoints.size(), 5u);
    for (int k = 0; k < 5; ++k) {
      EXPECT_EQ(im.keypoints[k].x(), 100.f * im.image_id + k + 0.25f);
      EXPECT_EQ(im.keypoints[k].y(), 7.f * k);
    }
  }
  ASSERT_EQ(db.two_view_geometries.size(), 3u);
  EXPECT_EQ(db.two_view_geometries[1].image_id1, 1u);  // ordered by pair id: (1,2), (1,5), (2,5)
  EXPECT_EQ(db.two_view_geometries[1].image_id2, 5u);
  EXPECT_EQ(db.two_view_geometries[2].config, 3);

  TrackStats stats;
  const Reconstruction rec = TracksFromColmapDatabase(db, {}, &stats);
  EXPECT_EQ(rec.CheckConsistency(), "");
  ASSERT_EQ(rec.points3D.size(), 3u);  // X = a0 b1 c2, Y = a3 b3, Z = b4 c4
  std::set<std::vector<std::pair<uint32_t, double>>> tracks;
  for (const auto& [id, p] : rec.points3D) {
    std::vector<std::pair<uint32_t, double>> t;
    for (const TrackElement& e : p.track)
      t.emplace_back(e.image_id, rec.images.at(e.image_id).points2D[e.point2D_idx].xy.x());
    tracks.insert(t);
  }
  const std::set<std::vector<std::pair<uint32_t, double>>> expected = {
      {{1, 100.25}, {2, 201.25}, {5, 502.25}}, {{1, 103.25}, {2, 203.25}}, {{2, 204.25}, {5, 504.25}}};
  EXPECT_TRUE(tracks == expected);
  EXPECT_EQ(rec.images.at(5).name, "c.jpg");
  EXPECT_EQ(rec.CameraOf(rec.images.at(5)).camera_id, 2u);
}

TEST(ColmapDatabase, UnverifiedConfigsAreIgnored) {
  const std::string path = TempPath("configs.db");
  {
    DbWriter w(path);
    w.Camera(1, 0, 100, 100, {90, 50, 50});
    for (int i = 1; i <= 4; ++i) {
      w.Image(i, "im" + std::to_string(i), 1);
      w.Keypoints(i, 5, 2, KeypointBlob(i, 2));
    }
    w.TwoView(1, 2, {{0, 0}}, 2);  // CALIBRATED: kept
    w.TwoView(1, 3, {{1, 1}}, 1);  // DEGENERATE
    w.TwoView(1, 4, {{2, 2}}, 7);  // WATERMARK
    w.TwoView(2, 3, {{3, 3}}, 0);  // UNDEFINED
    w.TwoView(2, 4, {{4, 4}}, 8);  // MULTIPLE
    w.TwoView(3, 4, {{0, 0}}, 6);  // PLANAR_OR_PANORAMIC: kept
  }
  const Reconstruction rec = TracksFromColmapDatabase(ReadColmapDatabase(path), {});
  ASSERT_EQ(rec.points3D.size(), 2u);
  EXPECT_EQ(rec.points3D.at(1).track[0].image_id, 1u);
  EXPECT_EQ(rec.points3D.at(1).track[1].image_id, 2u);
  EXPECT_EQ(rec.points3D.at(2).track[0].image_id, 3u);
  EXPECT_EQ(rec.images.size(), 4u);
}

TEST(ColmapDatabase, BadInputIsAnInputErrorNamingTheFile) {
  const std::string text = TempPath("not_a_db.db");
  std::ofstream(text) << "this is not sqlite\n";
  try {
    ReadColmapDatabase(text);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
  }
  EXPECT_THROW(ReadColmapDatabase(TempPath("missing.db")), InputError);

  const std::string fisheye = TempPath("fisheye.db");
  {
    DbWriter w(fisheye);
    w.Camera(1, 5, 100, 100, {90, 90, 50, 50, 0, 0, 0, 0});  // OPENCV_FISHEYE
  }
  EXPECT_THROW(ReadColmapDatabase(fisheye), InputError);

  const std::string short_blob = TempPath("short.db");
  {
    DbWriter w(short_blob);
    w.Camera(1, 1, 100, 100, {90, 90, 50, 50});
    w.Image(1, "a", 1);
    w.Keypoints(1, 5, 2, std::vector<float>(9, 0.f));  // 5 x 2 needs 10 floats
  }
  EXPECT_THROW(ReadColmapDatabase(short_blob), InputError);

  const std::string bad_match = TempPath("bad_match.db");
  {
    DbWriter w(bad_match);
    w.Camera(1, 1, 100, 100, {90, 90, 50, 50});
    w.Image(1, "a", 1);
    w.Image(2, "b", 1);
    w.Keypoints(1, 5, 2, KeypointBlob(1, 2));
    w.Keypoints(2, 5, 2, KeypointBlob(2, 2));
    w.TwoView(1, 2, {{0, 9}}, 2);  // feature 9 does not exist
  }
  EXPECT_THROW(TracksFromColmapDatabase(ReadColmapDatabase(bad_match), {}), InputError);

  const std::string empty_schema = TempPath("empty.db");
  {
    sqlite3* db = nullptr;
    fs::remove(empty_schema);
    sqlite3_open(empty_schema.c_str(), &db);
    sqlite3_exec(db, "CREATE TABLE foo (x INTEGER);", nullptr, nullptr, nullptr);
    sqlite3_close(db);
  }
  EXPECT_THROW(ReadColmapDatabase(empty_schema), InputError);
}

// A hostile shape: rows * cols * 4 bytes wraps to 0 for rows = 2^62, which an empty blob
// "matched" before, and the copy then read far beyond the blob (SIGSEGV).
TEST(ColmapDatabase, HugeDeclaredShapeIsAnInputErrorNotAHeapOverflow) {
  const int64_t huge = int64_t(1) << 62;
  for (const char* table : {"keypoints", "two_view_geometries"}) {
    const std::string path = TempPath(std::string("huge_") + table + ".db");
    {
      DbWriter w(path);
      w.Camera(1, 1, 100, 100, {90, 90, 50, 50});
      w.Image(1, "a", 1);
      w.Image(2, "b", 1);
      if (std::string(table) == "keypoints") {
        w.Sql("INSERT INTO keypoints VALUES (1, " + std::to_string(huge) + ", 4, x'')");
      } else {
        w.Keypoints(1, 5, 2, KeypointBlob(1, 2));
        w.Keypoints(2, 5, 2, KeypointBlob(2, 2));
        w.Sql("INSERT INTO two_view_geometries (pair_id, rows, cols, data, config) VALUES (2147483649, " +
              std::to_string(huge) + ", 2, x'', 2)");
      }
    }
    try {
      ReadColmapDatabase(path);
      ADD_FAILURE() << table << ": accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("bad shape"), std::string::npos) << e.what();
    }
  }
}

// COLMAP's schema makes names UNIQUE; a database without that constraint must not give a
// tracks model with two images of one name.
TEST(ColmapDatabase, DuplicateImageNameIsAnInputError) {
  const std::string path = TempPath("dup_names.db");
  {
    DbWriter w(path);
    w.Sql("DROP TABLE images; CREATE TABLE images (image_id INTEGER PRIMARY KEY, name TEXT, camera_id INTEGER)");
    w.Camera(1, 1, 100, 100, {90, 90, 50, 50});
    w.Image(1, "a.jpg", 1);
    w.Image(2, "a.jpg", 1);
  }
  try {
    ReadColmapDatabase(path);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), path + ": duplicate image name 'a.jpg'");
  }
}

// Integers are range-checked before narrowing: a camera_id 4294967297 became camera 1 (and
// replaced it); names must round-trip through a text model; keypoints must be finite; a
// database without a verified pair is no empty model.
TEST(ColmapDatabase, IdsNamesNumbersAndEmptyResultsAreChecked) {
  auto message = [](const std::function<void()>& f) -> std::string {
    try {
      f();
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  };
  const std::string wrapping = TempPath("wrapping.db");
  {
    DbWriter w(wrapping);
    w.Camera(1, 1, 100, 100, {70, 70, 50, 50});
    w.Sql("INSERT INTO cameras VALUES (4294967297, 1, 100, 100, x'" + std::string(64, '0') + "', 0)");
  }
  EXPECT_EQ(message([&] { ReadColmapDatabase(wrapping); }),
            wrapping + ": camera_id 4294967297 is out of range [0, 4294967295]");
  const std::string image_camera = TempPath("image_camera.db");
  {
    DbWriter w(image_camera);
    w.Sql("DROP TABLE images; CREATE TABLE images (image_id INTEGER PRIMARY KEY, name TEXT, camera_id INTEGER)");
    w.Camera(1, 1, 100, 100, {90, 90, 50, 50});
    w.Sql("INSERT INTO images VALUES (1, 'a.jpg', 4294967297)");
  }
  EXPECT_EQ(message([&] { ReadColmapDatabase(image_camera); }),
            image_camera + ": image 1 camera_id 4294967297 is out of range [0, 4294967295]");
  for (const std::string& name : {std::string(""), std::string("new\nline.jpg"), std::string("space.jpg ")}) {
    const std::string path = TempPath("name.db");
    {
      DbWriter w(path);
      w.Camera(1, 1, 100, 100, {90, 90, 50, 50});
      w.Image(1, name, 1);
    }
    EXPECT_EQ(message([&] { ReadColmapDatabase(path); }).rfind(path + ": image 1: ", 0), 0u) << name;
  }
  const std::string nan = TempPath("nan.db");
  {
    DbWriter w(nan);
    w.Camera(1, 1, 100, 100, {90, 90, 50, 50});
    w.Image(1, "a", 1);
    w.Keypoints(1, 1, 2, {1.f, std::numeric_limits<float>::infinity()});
  }
  EXPECT_EQ(message([&] { ReadColmapDatabase(nan); }), nan + ": keypoints of image 1: keypoint 0 is not finite");
  const std::string unverified = TempPath("unverified.db");
  {
    DbWriter w(unverified);
    w.Camera(1, 1, 100, 100, {90, 90, 50, 50});
    for (int i = 1; i <= 2; ++i) {
      w.Image(i, "im" + std::to_string(i), 1);
      w.Keypoints(i, 5, 2, KeypointBlob(i, 2));
    }
    w.TwoView(1, 2, {{0, 0}}, 1);  // DEGENERATE
  }
  EXPECT_NE(message([&] { TracksFromColmapDatabase(ReadColmapDatabase(unverified), {}, nullptr, unverified); })
                .find(unverified + ": no verified two-view geometry"),
            std::string::npos);
  const std::string focal = TempPath("focal.db");
  {
    DbWriter w(focal);
    w.Camera(1, 1, 100, 100, {1e-9, 1e-9, 50, 50});
  }
  EXPECT_NE(message([&] { ReadColmapDatabase(focal); }).find("camera 1: focal length 1e-09 px is implausible"),
            std::string::npos);
}

}  // namespace
}  // namespace pgba
