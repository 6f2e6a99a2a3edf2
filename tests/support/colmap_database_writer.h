// A COLMAP database written with COLMAP's schema (the tables and blob layouts of COLMAP
// 3.8's database.cc), for the tests that read one: the importer's (tests/io) and the CLI's
// (tests/apps).
#pragma once

#include <gtest/gtest.h>
#include <sqlite3.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace pgba::test {

// COLMAP 3.8's schema (database.cc), verbatim in structure.
inline const char* kSchema = R"(
CREATE TABLE cameras (camera_id INTEGER PRIMARY KEY AUTOINCREMENT NOT NULL, model INTEGER NOT NULL,
  width INTEGER NOT NULL, height INTEGER NOT NULL, params BLOB, prior_focal_length INTEGER NOT NULL);
CREATE TABLE images (image_id INTEGER PRIMARY KEY AUTOINCREMENT NOT NULL, name TEXT NOT NULL UNIQUE,
  camera_id INTEGER NOT NULL, prior_qw REAL, prior_qx REAL, prior_qy REAL, prior_qz REAL, prior_tx REAL,
  prior_ty REAL, prior_tz REAL, CONSTRAINT image_id_check CHECK(image_id >= 0 and image_id < 2147483647),
  FOREIGN KEY(camera_id) REFERENCES cameras(camera_id));
CREATE TABLE keypoints (image_id INTEGER PRIMARY KEY NOT NULL, rows INTEGER NOT NULL, cols INTEGER NOT NULL,
  data BLOB, FOREIGN KEY(image_id) REFERENCES images(image_id) ON DELETE CASCADE);
CREATE TABLE descriptors (image_id INTEGER PRIMARY KEY NOT NULL, rows INTEGER NOT NULL, cols INTEGER NOT NULL,
  data BLOB, FOREIGN KEY(image_id) REFERENCES images(image_id) ON DELETE CASCADE);
CREATE TABLE matches (pair_id INTEGER PRIMARY KEY NOT NULL, rows INTEGER NOT NULL, cols INTEGER NOT NULL,
  data BLOB);
CREATE TABLE two_view_geometries (pair_id INTEGER PRIMARY KEY NOT NULL, rows INTEGER NOT NULL,
  cols INTEGER NOT NULL, data BLOB, config INTEGER NOT NULL, F BLOB, E BLOB, H BLOB, qvec BLOB, tvec BLOB);
)";

class DbWriter {
 public:
  explicit DbWriter(const std::string& path) {
    std::filesystem::remove(path);
    EXPECT_EQ(sqlite3_open(path.c_str(), &db_), SQLITE_OK);
    EXPECT_EQ(sqlite3_exec(db_, kSchema, nullptr, nullptr, nullptr), SQLITE_OK) << sqlite3_errmsg(db_);
  }
  ~DbWriter() { sqlite3_close(db_); }

  void Camera(int id, int model, int w, int h, const std::vector<double>& params) {
    Exec("INSERT INTO cameras VALUES (?, ?, ?, ?, ?, 0)", [&](sqlite3_stmt* s) {
      sqlite3_bind_int(s, 1, id);
      sqlite3_bind_int(s, 2, model);
      sqlite3_bind_int(s, 3, w);
      sqlite3_bind_int(s, 4, h);
      sqlite3_bind_blob(s, 5, params.data(), static_cast<int>(params.size() * sizeof(double)), SQLITE_TRANSIENT);
    });
  }
  void Image(int id, const std::string& name, int camera_id) {
    Exec("INSERT INTO images (image_id, name, camera_id) VALUES (?, ?, ?)", [&](sqlite3_stmt* s) {
      sqlite3_bind_int(s, 1, id);
      sqlite3_bind_text(s, 2, name.c_str(), -1, SQLITE_TRANSIENT);
      sqlite3_bind_int(s, 3, camera_id);
    });
  }
  // rows x cols float32 (COLMAP writes 6 columns: x y a11 a12 a21 a22).
  void Keypoints(int image_id, int rows, int cols, const std::vector<float>& data) {
    Exec("INSERT INTO keypoints VALUES (?, ?, ?, ?)", [&](sqlite3_stmt* s) {
      sqlite3_bind_int(s, 1, image_id);
      sqlite3_bind_int(s, 2, rows);
      sqlite3_bind_int(s, 3, cols);
      sqlite3_bind_blob(s, 4, data.data(), static_cast<int>(data.size() * sizeof(float)), SQLITE_TRANSIENT);
    });
  }
  void TwoView(int id1, int id2, const std::vector<std::pair<uint32_t, uint32_t>>& m, int config) {
    std::vector<uint32_t> blob;
    for (auto [a, b] : m) blob.push_back(a), blob.push_back(b);
    const int64_t pair_id = int64_t(2147483647) * id1 + id2;  // COLMAP's ImagePairToPairId
    Exec("INSERT INTO two_view_geometries (pair_id, rows, cols, data, config) VALUES (?, ?, 2, ?, ?)",
         [&](sqlite3_stmt* s) {
           sqlite3_bind_int64(s, 1, pair_id);
           sqlite3_bind_int(s, 2, static_cast<int>(m.size()));
           sqlite3_bind_blob(s, 3, blob.data(), static_cast<int>(blob.size() * 4), SQLITE_TRANSIENT);
           sqlite3_bind_int(s, 4, config);
         });
  }

 private:
  template <typename F>
  void Exec(const char* sql, F bind) {
    sqlite3_stmt* s = nullptr;
    ASSERT_EQ(sqlite3_prepare_v2(db_, sql, -1, &s, nullptr), SQLITE_OK) << sqlite3_errmsg(db_);
    bind(s);
    EXPECT_EQ(sqlite3_step(s), SQLITE_DONE) << sqlite3_errmsg(db_);
    sqlite3_finalize(s);
  }
  sqlite3* db_ = nullptr;

 public:
  void Sql(const std::string& sql) {
    EXPECT_EQ(sqlite3_exec(db_, sql.c_str(), nullptr, nullptr, nullptr), SQLITE_OK) << sqlite3_errmsg(db_);
  }
};

}  // namespace pgba::test
