#include "pgba/io/colmap_database.h"

#include <sqlite3.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <memory>
#include <set>

#include "pgba/io/input_checks.h"
#include "pgba/util/error.h"
#include "pgba/util/input_file.h"

namespace pgba {
namespace {

struct DbCloser {
  void operator()(sqlite3* db) const { sqlite3_close(db); }
};
struct StmtFinalizer {
  void operator()(sqlite3_stmt* s) const { sqlite3_finalize(s); }
};
using Statement = std::unique_ptr<sqlite3_stmt, StmtFinalizer>;

Statement Prepare(sqlite3* db, const std::string& path, const char* sql) {
  sqlite3_stmt* stmt = nullptr;
  if (sqlite3_prepare_v2(db, sql, -1, &stmt, nullptr) != SQLITE_OK) {
    const std::string msg = sqlite3_errmsg(db);
    sqlite3_finalize(stmt);
    ThrowInputError(path, 0, "not a readable COLMAP database (" + msg + ")");
  }
  return Statement(stmt);
}

// Steps a statement; false at the end, InputError on a read error.
bool Step(sqlite3* db, sqlite3_stmt* stmt, const std::string& path) {
  const int rc = sqlite3_step(stmt);
  if (rc == SQLITE_ROW) return true;
  if (rc == SQLITE_DONE) return false;
  ThrowInputError(path, 0, std::string("database read failed (") + sqlite3_errmsg(db) + ")");
}

// A blob column holding a rows x cols matrix of T, checked against its declared shape. The
// shape comes from the file: bounded first, so that rows * cols * sizeof(T) cannot wrap
// (rows = 2^62 with an empty blob must be "bad shape", not a 0-byte match and a heap read).
constexpr int64_t kMaxBlobRows = int64_t(1) << 31;  // an SQLite blob holds < 2^31 bytes
constexpr int64_t kMaxBlobCols = 1 << 10;
template <typename T>
std::vector<T> ReadBlob(sqlite3_stmt* stmt, int col, int64_t rows, int64_t cols, const std::string& path,
                        const std::string& what) {
  if (rows < 0 || cols < 0 || rows > kMaxBlobRows || cols > kMaxBlobCols)
    ThrowInputError(path, 0,
                    what + ": bad shape " + std::to_string(rows) + " x " + std::to_string(cols));
  const size_t expected = static_cast<size_t>(rows * cols);
  const int bytes = sqlite3_column_bytes(stmt, col);
  const void* data = sqlite3_column_blob(stmt, col);
  if (static_cast<size_t>(bytes) != expected * sizeof(T))
    ThrowInputError(
        path, 0,
        what + ": blob of " + std::to_string(bytes) + " bytes, expected " + std::to_string(expected * sizeof(T)));
  std::vector<T> out(expected);
  if (expected > 0) std::memcpy(out.data(), data, bytes);
  return out;
}

// An integer column narrowed to `T` only once it is known to fit: a camera_id 4294967297
// must not become camera 1.
template <typename T>
T ColumnInRange(sqlite3_stmt* stmt, int col, int64_t lo, int64_t hi, const std::string& path, const std::string& what) {
  if (sqlite3_column_type(stmt, col) != SQLITE_INTEGER)
    ThrowInputError(path, 0, what + " is not an integer");
  const int64_t v = sqlite3_column_int64(stmt, col);
  if (v < lo || v > hi)
    ThrowInputError(path, 0,
                    what + " " + std::to_string(v) + " is out of range [" + std::to_string(lo) + ", " +
                        std::to_string(hi) + "]");
  return static_cast<T>(v);
}

void ReadCameras(sqlite3* db, const std::string& path, ColmapDatabase* out) {
  Statement stmt = Prepare(db, path, "SELECT camera_id, model, width, height, params FROM cameras ORDER BY camera_id");
  while (Step(db, stmt.get(), path)) {
    Camera cam;
    cam.camera_id = ColumnInRange<uint32_t>(stmt.get(), 0, 0, UINT32_MAX, path, "camera_id");
    const int model = ColumnInRange<int>(stmt.get(), 1, 0, 1000, path, "camera " + std::to_string(cam.camera_id) + " model");
    const std::string what = "camera " + std::to_string(cam.camera_id);
    // pgba's CameraModel values are COLMAP's model ids 0..4.
    if (model < 0 || model > static_cast<int>(CameraModel::kOpenCV))
      ThrowInputError(path, 0,
                      what + ": COLMAP camera model id " + std::to_string(model) +
                          " is not supported (SIMPLE_PINHOLE, PINHOLE, SIMPLE_RADIAL, RADIAL, OPENCV are)");
    cam.model = static_cast<CameraModel>(model);
    cam.width = ColumnInRange<int>(stmt.get(), 2, 1, 1000000, path, what + " width");
    cam.height = ColumnInRange<int>(stmt.get(), 3, 1, 1000000, path, what + " height");
    cam.params = ReadBlob<double>(stmt.get(), 4, CameraModelNumParams(cam.model), 1, path, what + " params");
    const std::string problem = CheckCamera(cam);
    if (!problem.empty()) ThrowInputError(path, 0, what + ": " + problem);
    if (!out->cameras.emplace(cam.camera_id, cam).second) ThrowInputError(path, 0, what + " listed twice");
  }
}

void ReadImagesAndKeypoints(sqlite3* db, const std::string& path, ColmapDatabase* out) {
  std::map<uint32_t, size_t> slot;
  std::set<std::string> names;  // images are matched by name downstream (as in colmap_text.cc)
  Statement images = Prepare(db, path, "SELECT image_id, name, camera_id FROM images ORDER BY image_id");
  while (Step(db, images.get(), path)) {
    KeypointImage im;
    im.image_id = ColumnInRange<uint32_t>(images.get(), 0, 0, kColmapMaxImageId - 1, path, "image_id");
    const std::string what = "image " + std::to_string(im.image_id);
    // The whole value, embedded NUL bytes included, so that CheckImageName sees them.
    const unsigned char* name = sqlite3_column_text(images.get(), 1);
    if (!name) ThrowInputError(path, 0, what + ": NULL image name");
    im.name.assign(reinterpret_cast<const char*>(name), sqlite3_column_bytes(images.get(), 1));
    if (const std::string problem = CheckImageName(im.name); !problem.empty())
      ThrowInputError(path, 0, what + ": " + problem);
    im.camera_id = ColumnInRange<uint32_t>(images.get(), 2, 0, UINT32_MAX, path, what + " camera_id");
    if (!out->cameras.count(im.camera_id))
      ThrowInputError(path, 0, what + " (" + QuotedName(im.name) + ") uses unknown camera " + std::to_string(im.camera_id));
    if (!names.insert(im.name).second) ThrowInputError(path, 0, "duplicate image name " + QuotedName(im.name));
    slot[im.image_id] = out->images.size();
    out->images.push_back(std::move(im));
  }
  Statement kps = Prepare(db, path, "SELECT image_id, rows, cols, data FROM keypoints");
  while (Step(db, kps.get(), path)) {
    const uint32_t image_id = ColumnInRange<uint32_t>(kps.get(), 0, 0, kColmapMaxImageId - 1, path, "keypoints image_id");
    const int64_t rows = sqlite3_column_int64(kps.get(), 1), cols = sqlite3_column_int64(kps.get(), 2);
    const std::string what = "keypoints of image " + std::to_string(image_id);
    const auto it = slot.find(image_id);
    if (it == slot.end()) ThrowInputError(path, 0, what + ": no such image");
    if (rows < 0 || (rows > 0 && cols < 2)) ThrowInputError(path, 0, what + ": bad shape");
    const std::vector<float> data =
        ReadBlob<float>(kps.get(), 3, rows, rows > 0 ? cols : 0, path, what);
    std::vector<Eigen::Vector2d>& kp = out->images[it->second].keypoints;
    kp.resize(rows);
    for (int64_t r = 0; r < rows; ++r) {
      kp[r] = Eigen::Vector2d(data[r * cols], data[r * cols + 1]);
      if (!kp[r].allFinite()) ThrowInputError(path, 0, what + ": keypoint " + std::to_string(r) + " is not finite");
    }
  }
}

void ReadTwoViewGeometries(sqlite3* db, const std::string& path, ColmapDatabase* out) {
  std::set<uint32_t> ids;
  for (const KeypointImage& im : out->images) ids.insert(im.image_id);
  Statement stmt =
      Prepare(db, path, "SELECT pair_id, rows, cols, data, config FROM two_view_geometries ORDER BY pair_id");
  while (Step(db, stmt.get(), path)) {
    const uint64_t pair_id = ColumnInRange<uint64_t>(stmt.get(), 0, 0, INT64_MAX, path, "pair_id");
    ColmapTwoViewGeometry g;
    if (pair_id / kColmapMaxImageId >= kColmapMaxImageId)
      ThrowInputError(path, 0, "pair_id " + std::to_string(pair_id) + " is out of range (image ids < 2147483647)");
    g.image_id2 = static_cast<uint32_t>(pair_id % kColmapMaxImageId);
    g.image_id1 = static_cast<uint32_t>(pair_id / kColmapMaxImageId);
    g.config = ColumnInRange<int>(stmt.get(), 4, INT32_MIN, INT32_MAX, path, "two-view geometry config");
    const std::string what = "two-view geometry " + std::to_string(g.image_id1) + "-" + std::to_string(g.image_id2);
    if (!ids.count(g.image_id1) || !ids.count(g.image_id2)) ThrowInputError(path, 0, what + ": unknown image");
    const int64_t rows = sqlite3_column_int64(stmt.get(), 1), cols = sqlite3_column_int64(stmt.get(), 2);
    if (rows < 0 || (rows > 0 && cols != 2)) ThrowInputError(path, 0, what + ": bad shape");
    const std::vector<uint32_t> data = ReadBlob<uint32_t>(stmt.get(), 3, rows, 2, path, what);
    g.inlier_matches.resize(rows);
    for (int64_t r = 0; r < rows; ++r) g.inlier_matches[r] = {data[2 * r], data[2 * r + 1]};
    out->two_view_geometries.push_back(std::move(g));
  }
}

}  // namespace

bool IsVerifiedColmapConfig(int config) { return config >= 2 && config <= 6; }

ColmapDatabase ReadColmapDatabase(const std::string& path) {
  RequireRegularFile(path);
  sqlite3* raw = nullptr;
  if (sqlite3_open_v2(path.c_str(), &raw, SQLITE_OPEN_READONLY, nullptr) != SQLITE_OK) {
    const std::string msg = raw ? sqlite3_errmsg(raw) : "out of memory";
    sqlite3_close(raw);
    ThrowInputError(path, 0, "cannot open database (" + msg + ")");
  }
  std::unique_ptr<sqlite3, DbCloser> db(raw);
  ColmapDatabase out;
  ReadCameras(db.get(), path, &out);
  ReadImagesAndKeypoints(db.get(), path, &out);
  ReadTwoViewGeometries(db.get(), path, &out);
  return out;
}

Reconstruction TracksFromColmapDatabase(const ColmapDatabase& db, const TrackBuilderOptions& options, TrackStats* stats,
                                        const std::string& source) {
  std::vector<PairMatches> pairs;
  for (const ColmapTwoViewGeometry& g : db.two_view_geometries) {
    if (!IsVerifiedColmapConfig(g.config) || g.inlier_matches.empty()) continue;
    pairs.push_back({g.image_id1, g.image_id2, g.inlier_matches});
  }
  // An empty tracks model would read as a result: a database matched but never verified
  // (colmap *_matcher without geometric verification) is named as such.
  if (pairs.empty())
    ThrowInputError(source, 0,
                    "no verified two-view geometry (two_view_geometries holds " +
                        std::to_string(db.two_view_geometries.size()) +
                        " rows, none verified with inliers): run COLMAP's matcher with geometric verification");
  return BuildTracks(db.cameras, db.images, pairs, options, stats, source);
}

}  // namespace pgba
