// Multi-view triangulation of one track with known poses: linear (DLT on unit bearings),
// then robust Gauss-Newton on pixel reprojection errors (Huber IRLS), with a pairwise
// consensus restart when the linear solution is pulled by an outlier observation.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "pgba/geometry/pose.h"
#include "pgba/scene/camera.h"

namespace pgba {

struct TrackView {
  Pose pose;
  const Camera* camera = nullptr;
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();
};

struct TriangulationOptions {
  // Huber threshold of the Gauss-Newton refinement, pixels.
  double huber_px = 1.0;
  // Observations above this are outliers for the consensus restart, pixels.
  double outlier_px = 4.0;
  // Gauss-Newton iterations.
  int max_iterations = 10;
  // Minimum triangulation angle (degrees) between the two most separated rays; below it the
  // depth is unobservable and the track is rejected.
  double min_angle_deg = 0.0;
};

struct TriangulatedPoint {
  bool ok = false;
  Eigen::Vector3d X = Eigen::Vector3d::Zero();
  std::vector<double> residuals_px;  // one per view, same order as the input
  double max_angle_deg = 0.0;
};

// Linear triangulation from camera-frame unit bearings b_i and poses: minimises
// sum ||b_i x (R_i X + t_i)||^2 over homogeneous X. False if degenerate or at infinity.
bool TriangulateLinear(const std::vector<Pose>& poses, const std::vector<Eigen::Vector3d>& bearings,
                       Eigen::Vector3d* X);

// Full robust triangulation. ok = false when fewer than 2 views, the point is behind a
// camera, or the angle is below options.min_angle_deg.
TriangulatedPoint TriangulateTrack(const std::vector<TrackView>& views, const TriangulationOptions& options = {});

// Largest angle (degrees) between the viewing rays from the centres to X.
double MaxTriangulationAngleDeg(const std::vector<TrackView>& views, const Eigen::Vector3d& X);

}  // namespace pgba
