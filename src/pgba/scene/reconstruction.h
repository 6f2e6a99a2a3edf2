// The scene: cameras (intrinsics), images (pose + 2D observations), 3D points with their
// tracks. Mirrors COLMAP's model so that text models round-trip, and is the container that
// every stage reads (observations and tracks) and writes (poses, points).
//
// Ids are COLMAP's: camera_id and image_id are uint32, point3D_id uint64. std::map keeps
// iteration order deterministic (ordered by id).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "pgba/geometry/pose.h"
#include "pgba/scene/camera.h"

namespace pgba {

constexpr int64_t kNoPoint3D = -1;

struct Point2D {
  Eigen::Vector2d xy = Eigen::Vector2d::Zero();  // pixels
  int64_t point3D_id = kNoPoint3D;
};

struct Image {
  uint32_t image_id = 0;
  std::string name;
  uint32_t camera_id = 0;
  Pose pose;
  std::vector<Point2D> points2D;
};

struct TrackElement {
  uint32_t image_id = 0;
  uint32_t point2D_idx = 0;
};

struct Point3D {
  uint64_t point3D_id = 0;
  Eigen::Vector3d xyz = Eigen::Vector3d::Zero();
  Eigen::Matrix<uint8_t, 3, 1> color = Eigen::Matrix<uint8_t, 3, 1>::Constant(128);
  double error = -1.0;  // mean reprojection error in px, -1 if unknown (COLMAP writes -1 too)
  std::vector<TrackElement> track;
};

class Reconstruction {
 public:
  std::map<uint32_t, Camera> cameras;
  std::map<uint32_t, Image> images;
  std::map<uint64_t, Point3D> points3D;

  const Camera& CameraOf(const Image& image) const { return cameras.at(image.camera_id); }
  // Image id by file name, nullopt if absent.
  std::optional<uint32_t> FindImageByName(const std::string& name) const;
  size_t NumObservations() const;

  // Adds a point with the given track, linking each observation's point3D_id back to it.
  // Returns the new id (max id + 1). Throws (leaving the scene unchanged) std::out_of_range
  // if an element names a missing image or observation, std::invalid_argument if an
  // observation already belongs to a point or is listed twice.
  uint64_t AddPoint3D(const Eigen::Vector3d& xyz, std::vector<TrackElement> track);
  // Removes a point and unlinks its observations.
  void DeletePoint3D(uint64_t point3D_id);
  // Keeps only the listed images (and the tracks' elements in them); points left with fewer
  // than 2 observations are removed.
  void KeepImages(const std::vector<uint32_t>& image_ids);

  // Empty if every reference resolves (image -> camera, track -> image/point2D and back, no
  // element listed twice, map keys equal to the stored ids); otherwise the first
  // inconsistency found.
  std::string CheckConsistency() const;
};

}  // namespace pgba
