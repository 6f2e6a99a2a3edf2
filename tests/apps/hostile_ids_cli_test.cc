// Hostile ids and shapes: every integer read from a file or a database is range-checked
// before narrowing, and a database's declared shapes against its blobs.
#include <gtest/gtest.h>
#include <cstdint>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "tests/apps/hostile_cli_fixture.h"
#include "tests/support/colmap_database_writer.h"

namespace {
namespace fs = std::filesystem;
using pgba::test::Bytes;
using pgba::test::Lines;

class HostileIdsCli : public pgba::test::HostileCli {};

// Crash: a COLMAP database row declaring rows = 2^62 over an empty blob (the blob size check
// wrapped; SIGSEGV in init and match).
TEST_F(HostileIdsCli, DatabaseWithHugeDeclaredShape) {
  const std::string huge = std::to_string(int64_t(1) << 62);
  const fs::path keypoints = dir_ / "huge_keypoints.db", geometries = dir_ / "huge_geometries.db";
  {
    pgba::test::DbWriter w(keypoints.string());
    w.Camera(1, 1, 100, 100, {90, 90, 50, 50});
    w.Image(1, "a.jpg", 1);
    w.Image(2, "b.jpg", 1);
    w.Sql("INSERT INTO keypoints VALUES (1, " + huge + ", 2, x'')");
  }
  {
    pgba::test::DbWriter w(geometries.string());
    w.Camera(1, 1, 100, 100, {90, 90, 50, 50});
    w.Image(1, "a.jpg", 1);
    w.Image(2, "b.jpg", 1);
    w.Keypoints(1, 1, 2, {10.f, 20.f});
    w.Keypoints(2, 1, 2, {30.f, 40.f});
    w.Sql("INSERT INTO two_view_geometries (pair_id, rows, cols, data, config) VALUES (2147483649, " + huge +
          ", 2, x'', 2)");
  }
  for (const fs::path& db : {keypoints, geometries}) {
    ExpectOneLineError(Run("init --database " + db.string() + " --out " + (dir_ / "db_ws").string()), db.string(),
                       "bad shape");
    ExpectOneLineError(Run("match --database " + db.string() + " --out " + (dir_ / "db_ws").string()),
                       db.string(), "bad shape");
    EXPECT_FALSE(fs::exists(dir_ / "db_ws" / "tracks"));
  }
}

// Ids: a camera_id 4294967297 wrapped to 1 and silently replaced camera 1; a camera map line
// likewise.
TEST_F(HostileIdsCli, IdsBeyondTheirRangeAreRefused) {
  const fs::path db = dir_ / "wrapping_ids.db";
  {
    pgba::test::DbWriter w(db.string());
    w.Camera(1, 1, 100, 100, {70, 70, 50, 50});
    w.Sql("INSERT INTO cameras VALUES (4294967297, 1, 100, 100, x'" + std::string(64, '0') + "', 0)");
  }
  ExpectOneLineError(Run("init --database " + db.string() + " --out " + (dir_ / "ids_ws").string()), db.string(),
                     "camera_id 4294967297 is out of range");
  const fs::path images = Photos("map_ids");
  const fs::path calib = dir_ / "map_ids" / "two_cameras.txt", map = dir_ / "map_ids" / "map.txt";
  std::ofstream(calib) << "1 PINHOLE 320 240 300 300 160 120\n2 PINHOLE 320 240 310 310 160 120\n";
  std::ofstream(map) << "im0.jpg 1\nim1.jpg 4294967297\nim2.jpg 2\n";
  ExpectOneLineError(Run("features --images " + images.string() + " --calib " + calib.string() + " --camera-map " +
                         map.string() + " --out " + (dir_ / "map_ws").string()),
                     map.string() + ":2", "camera 4294967297 is not in the calibration");
}

// Empty results: a database matched without geometric verification gave an empty tracks
// model and exit 0.
TEST_F(HostileIdsCli, DatabaseWithoutVerifiedGeometriesIsAnError) {
  const fs::path db = dir_ / "unverified.db";
  {
    pgba::test::DbWriter w(db.string());
    w.Camera(1, 1, 100, 100, {90, 90, 50, 50});
    w.Image(1, "a.jpg", 1);
    w.Image(2, "b.jpg", 1);
    w.Keypoints(1, 1, 2, {10.f, 20.f});
    w.Keypoints(2, 1, 2, {30.f, 40.f});
    w.TwoView(1, 2, {{0, 0}}, 0);  // UNDEFINED: matched, never verified
  }
  ExpectOneLineError(Run("match --database " + db.string() + " --out " + (dir_ / "unverified_ws").string()),
                     db.string(), "no verified two-view geometry");
  EXPECT_FALSE(fs::exists(dir_ / "unverified_ws" / "tracks"));
}

}  // namespace
