// COLMAP's SQLite database (database.db of `colmap feature_extractor` + `*_matcher`) as an
// alternative front end, as GLOMAP uses it: cameras, images, keypoints and the verified
// matches of two_view_geometries become pgba's tracks model through the same union-find as
// our own matches (scene/track_builder.h).
//
// Tables read (schema of COLMAP's database.cc; extra columns are ignored):
//   cameras(camera_id, model, width, height, params BLOB of float64, prior_focal_length)
//   images(image_id, name, camera_id, ...)
//   keypoints(image_id, rows, cols, data BLOB of rows x cols float32; columns 0, 1 = x, y)
//   two_view_geometries(pair_id, rows, cols, data BLOB of rows x 2 uint32, config, ...)
// pair_id = image_id1 * 2147483647 + image_id2 with image_id1 < image_id2, and the match
// columns follow that order. Only pairs COLMAP verified are used: config CALIBRATED (2),
// UNCALIBRATED (3), PLANAR (4), PANORAMIC (5), PLANAR_OR_PANORAMIC (6); UNDEFINED (0),
// DEGENERATE (1), WATERMARK (7) and MULTIPLE (8) are skipped. COLMAP's pixel convention
// (pixel centres at +0.5) is pgba's, so keypoints are taken as they are.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "pgba/scene/reconstruction.h"
#include "pgba/scene/track_builder.h"

namespace pgba {

constexpr uint64_t kColmapMaxImageId = 2147483647;

inline uint64_t ColmapPairId(uint32_t image_id1, uint32_t image_id2) {
  if (image_id1 > image_id2) std::swap(image_id1, image_id2);
  return kColmapMaxImageId * image_id1 + image_id2;
}

struct ColmapTwoViewGeometry {
  uint32_t image_id1 = 0;
  uint32_t image_id2 = 0;
  int config = 0;
  std::vector<std::pair<uint32_t, uint32_t>> inlier_matches;
};

struct ColmapDatabase {
  std::map<uint32_t, Camera> cameras;
  std::vector<KeypointImage> images;  // with their keypoints, sorted by image id
  std::vector<ColmapTwoViewGeometry> two_view_geometries;
};

// Whether a two_view_geometries config means "verified" (see above).
bool IsVerifiedColmapConfig(int config);

// Reads the whole database. InputError naming the file for: a file that is not a SQLite
// database or lacks a table, an unsupported camera model, a parameter blob of the wrong
// size, a keypoint or match blob whose size does not match rows x cols, an image of an
// unknown camera, a pair of unknown images.
ColmapDatabase ReadColmapDatabase(const std::string& path);

// The tracks model of the verified pairs (images without keypoints keep no points2D).
Reconstruction TracksFromColmapDatabase(const ColmapDatabase& db, const TrackBuilderOptions& options,
                                        TrackStats* stats = nullptr, const std::string& source = "database");

}  // namespace pgba
