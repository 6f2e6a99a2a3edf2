// The local bundle adjustment of one relative motion (paper eq. 1) in the motion's frame: its
// N poses (PoseBlock, the shared [C, omega] chart), its points triangulated from the local
// poses, and the observations of those points in the N views.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "modules/local_hessian/local_hessian.h"
#include "pgba/optim/intrinsics.h"
#include "pgba/optim/pose_parameterization.h"

namespace pgba {

struct LocalObservation {
  int view = 0;   // 0..N-1, position in LocalMotion::image_ids
  int point = 0;  // index into LocalBundleProblem::points
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();
  // Relative weight of this observation's squared residual (times observation_weight).
  double weight = 1.0;
};

// Self-calibration (paper, "Self-calibrating bundle adjustment"): the motion's cameras whose
// intrinsics are unknowns. Their parameters are copies (the local BA estimates them), and h
// grows from 6N to 6N + K rows, K the number of free parameters over these cameras, in the
// order of `camera_ids` and, within a camera, of `free` (FreeIntrinsicIndices).
struct LocalIntrinsics {
  std::vector<uint32_t> camera_ids;      // ascending
  std::vector<Camera> cameras;           // their current values
  std::vector<std::vector<int>> free;    // indices into Camera::params
  // IntrinsicDirections of each camera: fixed, since the adjustment moves its parameters
  // along them (an aspect ratio it holds stays the one it started from).
  std::vector<Eigen::MatrixXd> directions;
  std::vector<int> offset;               // row of each camera's first unknown within the K
  int num_unknowns = 0;                  // K
};

struct LocalBundleProblem {
  std::vector<PoseBlock> poses;
  // Camera of each view as in `tracks` (CameraOf: with the current free intrinsics).
  std::vector<const Camera*> cameras;
  // Per view, its camera's index in intrinsics.camera_ids, or -1 for a held camera.
  std::vector<int> view_intrinsics;
  LocalIntrinsics intrinsics;
  std::vector<Eigen::Vector3d> points;
  std::vector<int> point_track;  // per point, its index in LocalMotion::track_ids
  // Grouped by point (all observations of point i are contiguous, in view order).
  std::vector<LocalObservation> observations;
  // Weight of each squared residual: gamma / M (paper's attenuation), 1 if disabled.
  double observation_weight = 1.0;
  // Robust loss and its scale in pixels (LocalHessianOptions::loss).
  LossFunctionOptions loss = {LossType::kHuber, 1.0};
  // Optional pose prior of the local BA (PriorPlacement::kLocalBAAndHessian): cost
  // 1/2 (x - x_in)^T prior (x - x_in) over the stacked 6N-vector of the pose blocks,
  // centred at the input poses (empty: none).
  Eigen::MatrixXd prior;
  Eigen::VectorXd prior_center;
  // Observations of the motion's tracks in its views before the gross-outlier filter (those
  // of tracks that failed to triangulate included): the denominator of RobustCost.
  int num_candidate_observations = 0;
  // Observations beyond this were dropped, and RobustCost caps every error here
  // (LocalHessianOptions: max_reprojection_px, or cauchy_max_reprojection_px for Cauchy).
  double max_reprojection_px = 4.0;

  int num_views() const { return static_cast<int>(poses.size()); }
  // Unknowns of h: 6N pose coordinates, then the K intrinsics.
  int num_unknowns() const { return 6 * num_views() + intrinsics.num_unknowns; }
  const Camera& CameraOf(int view) const {
    const int c = view_intrinsics[view];
    return c >= 0 ? intrinsics.cameras[c] : *cameras[view];
  }
};

// The motion's robust reprojection cost at its current poses and points: the loss (rho of
// the squared pixel error, scale huber_px) of every kept observation, and its value at
// max_reprojection_px for every candidate observation the filter dropped, so that costs at
// different poses compare over the same observations (the checked re-linearisation of the
// global BA accepts a step by it).
double RobustCost(const LocalBundleProblem& problem);

// gamma / M with gamma = M Q / (M + Q) (paper, implementation details); 1 for Q <= 0 or inf.
double AttenuationWeight(int num_points, double q);

// Collects the motion's tracks from the tracks model, triangulates each from the local poses
// (TriangulateTrack), drops gross outlier observations and points with < 2 views. Returns
// kOk, kInvalidInput or kTooFewPoints. `free` (nullptr: none) selects the intrinsic unknowns.
LocalHessianStatus BuildLocalBundleProblem(const Reconstruction& tracks, const LocalMotion& motion,
                                           const LocalHessianOptions& options, LocalBundleProblem* problem,
                                           const ObservationShares* shares = nullptr,
                                           const FreeIntrinsics* free = nullptr);

// Runs the solve `solver` describes (LocalBundleSolverOptions: Levenberg-Marquardt, DENSE_SCHUR
// with the points eliminated first, single thread) on poses, points and the free intrinsics
// (nothing when solver.max_iterations is 0), then re-linearises the poses
// (omega folded into R0) so that h is taken in the chart centred at the solution. False if
// Ceres could not evaluate the problem.
// With `fix_gauge` the first pose and the largest baseline coordinate of the second are held
// (a BA that must converge from afar, local_motions.h; the local Hessian's single step runs
// gauge-free instead, so that h is the plain normal matrix).
bool SolveLocalBundle(const SolverOptions& solver, LocalBundleProblem* problem, bool fix_gauge = false);

// Median depth of the observed points in their cameras (local frame units).
double MedianDepth(const LocalBundleProblem& problem);

// Unweighted RMS pixel reprojection error.
double RmsReprojectionPx(const LocalBundleProblem& problem);

}  // namespace pgba
