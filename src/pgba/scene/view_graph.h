// The view graph's edges: verified image pairs with their relative pose. Its triplets are
// relative motions of three views (local_motion.h).
#pragma once

#include <Eigen/Core>
#include <cstdint>

#include "pgba/geometry/pose.h"
#include "pgba/scene/local_motion.h"

namespace pgba {

// Relative geometry of a pair: x_2 = R_21 x_1 + t_21 with |t_21| = 1 (camera frames).
struct TwoViewGeometry {
  uint32_t image_id1 = 0;
  uint32_t image_id2 = 0;
  Eigen::Matrix3d R_21 = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t_21 = Eigen::Vector3d::UnitX();
  int num_tracks = 0;   // tracks shared by the two images
  int num_inliers = 0;  // of the essential-matrix fit
  double median_triangulation_angle_deg = 0.0;
};

}  // namespace pgba
