// Fuzz target: the COLMAP database reader (pgba/io/colmap_database.h) and the tracks built
// from it. Bytes of a whole SQLite file: mutations reach the record headers (declared rows
// and cols, blob sizes: the rows = 2^62 heap overflow) as well as the page structure.
#include "pgba/io/colmap_database.h"

#include <sqlite3.h>

#include <cstring>
#include <filesystem>

#include "pgba/util/input_file.h"
#include "tests/fuzz/fuzz_support.h"

namespace pgba::fuzz {
namespace {

void Exec(sqlite3* db, const std::string& sql) { sqlite3_exec(db, sql.c_str(), nullptr, nullptr, nullptr); }

std::string Blob(const void* data, size_t bytes) {
  static const char* hex = "0123456789abcdef";
  std::string s = "x'";
  for (size_t i = 0; i < bytes; ++i) {
    const unsigned char c = static_cast<const unsigned char*>(data)[i];
    s += hex[c >> 4];
    s += hex[c & 15];
  }
  return s + "'";
}

// A database with COLMAP's schema: two cameras, three images of 4 keypoints, three verified
// pairs; `keypoint_rows` and `match_rows` are the declared row counts (hostile when they do
// not match the blobs).
std::string MakeDatabase(const std::string& name, int64_t keypoint_rows, int64_t match_rows) {
  const std::string path = (ScratchDir() / name).string();
  std::filesystem::remove(path);
  sqlite3* db = nullptr;
  sqlite3_open(path.c_str(), &db);
  Exec(db,
       "CREATE TABLE cameras (camera_id INTEGER PRIMARY KEY, model INTEGER, width INTEGER, height INTEGER, "
       "params BLOB, prior_focal_length INTEGER);"
       "CREATE TABLE images (image_id INTEGER PRIMARY KEY, name TEXT UNIQUE, camera_id INTEGER);"
       "CREATE TABLE keypoints (image_id INTEGER PRIMARY KEY, rows INTEGER, cols INTEGER, data BLOB);"
       "CREATE TABLE two_view_geometries (pair_id INTEGER PRIMARY KEY, rows INTEGER, cols INTEGER, data BLOB, "
       "config INTEGER);");
  const double pinhole[4] = {500, 500, 320, 240}, radial[4] = {600, 400, 300, 0.01};
  Exec(db, "INSERT INTO cameras VALUES (1, 1, 640, 480, " + Blob(pinhole, sizeof(pinhole)) + ", 0)");
  Exec(db, "INSERT INTO cameras VALUES (2, 2, 800, 600, " + Blob(radial, sizeof(radial)) + ", 0)");
  for (int i = 1; i <= 3; ++i) {
    Exec(db, "INSERT INTO images VALUES (" + std::to_string(i) + ", 'im" + std::to_string(i) + ".jpg', " +
                 std::to_string(i == 3 ? 2 : 1) + ")");
    float kp[4 * 6];
    for (int k = 0; k < 24; ++k) kp[k] = static_cast<float>(10 * i + k);
    Exec(db, "INSERT INTO keypoints VALUES (" + std::to_string(i) + ", " + std::to_string(keypoint_rows) + ", 6, " +
                 Blob(kp, sizeof(kp)) + ")");
  }
  const uint32_t matches[6] = {0, 1, 1, 2, 3, 3};
  for (auto [a, b] : {std::pair<int, int>{1, 2}, {1, 3}, {2, 3}})
    Exec(db, "INSERT INTO two_view_geometries VALUES (" + std::to_string(int64_t(2147483647) * a + b) + ", " +
                 std::to_string(match_rows) + ", 2, " + Blob(matches, sizeof(matches)) + ", 2)");
  sqlite3_close(db);
  return ReadRegularFile(path);
}

}  // namespace

std::vector<std::string> Seeds() {
  return {MakeDatabase("seed_ok.db", 4, 3), MakeDatabase("seed_huge_keypoints.db", int64_t(1) << 62, 3),
          MakeDatabase("seed_huge_matches.db", 4, int64_t(1) << 62), MakeDatabase("seed_negative.db", -1, -3)};
}

}  // namespace pgba::fuzz

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace pgba;
  const std::string path = fuzz::WriteScratchFile("input.db", fuzz::Bytes(data, size));
  fuzz::ExpectValueOrInputError(path, [&] {
    const ColmapDatabase db = ReadColmapDatabase(path);
    const Reconstruction tracks = TracksFromColmapDatabase(db, TrackBuilderOptions{}, nullptr, path);
    fuzz::Require(tracks.CheckConsistency().empty(), "inconsistent tracks: " + tracks.CheckConsistency());
  });
  return 0;
}
