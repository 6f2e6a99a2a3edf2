// Calibrated absolute pose of one view from 2D-3D correspondences: OpenGV's P3P (Kneip)
// or EPnP inside OpenGV's RANSAC (seeded), then OpenGV's nonlinear refinement on the
// inliers. It places the third view of a triplet on points triangulated from the
// first two, which gives the triplet one consistent scale.
#pragma once

#include <nlohmann/json.hpp>

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "pgba/geometry/pose.h"

namespace pgba {

struct AbsolutePoseOptions {
  // Inlier threshold on the reprojection error, pixels (converted to an angle with the
  // focal length; OpenGV compares 1 - cos(angle between bearing and reprojection)).
  double threshold_px = 3.0;
  // Minimal solver: "p3p_kneip", "p3p_gao" or "epnp".
  std::string algorithm = "p3p_kneip";
  int max_iterations = 1000;
  double confidence = 0.9999;
  uint64_t seed = 0;
  int min_inliers = 12;
  // Empty when valid, else one line naming the first field out of its valid range (the
  // ranges of io/option_ranges.cc) or breaking a rule between fields.
  std::string Check() const;
};
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(AbsolutePoseOptions, threshold_px, algorithm, max_iterations,
                                                confidence, seed, min_inliers)

struct AbsolutePoseResult {
  bool success = false;
  Pose pose;  // world -> camera (x_cam = R (X - C))
  std::vector<uint8_t> inlier_mask;
  int num_inliers = 0;
};

// bearings[i] (unit, camera frame) observe points[i] (world). Throws std::invalid_argument
// for mismatched sizes, non-positive focal or an unknown algorithm.
AbsolutePoseResult EstimateAbsolutePose(const std::vector<Eigen::Vector3d>& bearings,
                                        const std::vector<Eigen::Vector3d>& points, double focal_px,
                                        const AbsolutePoseOptions& options);

}  // namespace pgba
