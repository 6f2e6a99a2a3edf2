// Multi-view triangulation of one track with known poses: linear (DLT on unit bearings),
// then robust Gauss-Newton on pixel reprojection errors (Huber IRLS, final pass on the
// inlier views only), with a pairwise consensus restart when the linear solution is pulled
// by an outlier observation.
#pragma once

#include <string>

#include <Eigen/Core>
#include <limits>
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
  // Observations above this are outliers, pixels: they choose the consensus restart and are
  // left out of the final refinement and of the angle test.
  double outlier_px = 4.0;
  // Gauss-Newton iterations per refinement (Huber IRLS converges linearly; most tracks stop
  // early on the step-size test, 30 lets the slow ones converge to ~1e-5 px).
  int max_iterations = 30;
  // Minimum triangulation angle (degrees) between the two most separated rays; below it the
  // depth is unobservable and the track is rejected.
  double min_angle_deg = 0.0;
  // Empty when valid, else one line naming the first field out of its valid range (the
  // ranges of io/option_ranges.cc) or breaking a rule between fields.
  std::string Check() const;
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

// Full robust triangulation. ok = false when fewer than 2 views, the linear problem is
// degenerate (parallel rays), fewer than 2 cameras see the point in front of them, or the
// angle between supporting rays is below options.min_angle_deg. Views that see the point
// behind them get residual 1e30 (they are outliers, not a reason to reject the track).
// When fewer than 2 views are within outlier_px (e.g. poor poses), the point is the Huber
// estimate over all views in front, so errors of bad poses are still measurable.
TriangulatedPoint TriangulateTrack(const std::vector<TrackView>& views, const TriangulationOptions& options = {});

// A track's point from a previous triangulation over nearby poses, and how many views
// supported it (reprojection error below outlier_px).
struct PointStart {
  Eigen::Vector3d X = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
  int support = 0;
};

// TriangulateTrack from a start near the solution: robust refinement from start.X, kept if
// at least start.support views support it, else the full search of TriangulateTrack.
// Re-linearisation passes re-triangulate every track after a small pose step; the linear
// solution and the consensus restart (O(n^3) projections on a track holding an outlier) were
// half of such a pass. The support test keeps a start that a large step moved into another
// basin from deciding the point: the full search then runs as without a start.
TriangulatedPoint TriangulateTrackFrom(const std::vector<TrackView>& views, const PointStart& start,
                                       const TriangulationOptions& options = {});

// Largest angle (degrees) between the viewing rays from the centres to X.
double MaxTriangulationAngleDeg(const std::vector<TrackView>& views, const Eigen::Vector3d& X);

}  // namespace pgba
