// The local bundle adjustment of one triplet (paper eq. 1) in the triplet's frame: its
// three poses (PoseBlock, the shared [C, omega] chart), its points triangulated from the
// local poses, and the observations of those points in the three views.
#pragma once

#include <Eigen/Core>
#include <array>
#include <vector>

#include "modules/local_hessian/local_hessian.h"
#include "pgba/optim/pose_parameterization.h"

namespace pgba {

struct LocalObservation {
  int view = 0;   // 0..2, position in Triplet::image_ids
  int point = 0;  // index into LocalBundleProblem::points
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();
  // Relative weight of this observation's squared residual (times observation_weight).
  double weight = 1.0;
};

struct LocalBundleProblem {
  std::array<PoseBlock, 3> poses;
  std::array<const Camera*, 3> cameras{};
  std::vector<Eigen::Vector3d> points;
  // Grouped by point (all observations of point i are contiguous, in view order).
  std::vector<LocalObservation> observations;
  // Weight of each squared residual: gamma / M (paper's attenuation), 1 if disabled.
  double observation_weight = 1.0;
  double huber_px = 1.0;
  // Optional pose prior of the local BA (PriorPlacement::kLocalBAAndHessian): cost
  // 1/2 (x - x_in)^T prior (x - x_in) over the stacked 18-vector of the three pose blocks,
  // centred at the input poses.
  Matrix18d prior = Matrix18d::Zero();
  Vector18d prior_center = Vector18d::Zero();
};

// gamma / M with gamma = M Q / (M + Q) (paper, implementation details); 1 for Q <= 0 or inf.
double AttenuationWeight(int num_points, double q);

// Collects the triplet's tracks from the tracks model, triangulates each from the local poses
// (TriangulateTrack), drops gross outlier observations and points with < 2 views. Returns
// kOk, kInvalidInput or kTooFewPoints.
LocalHessianStatus BuildLocalBundleProblem(const Reconstruction& tracks, const Triplet& triplet,
                                           const LocalHessianOptions& options, LocalBundleProblem* problem,
                                           const ObservationShares* shares = nullptr);

// Runs `max_iterations` Levenberg-Marquardt iterations (Ceres, DENSE_SCHUR, single thread:
// triplets are parallelised outside) on poses and points, then re-linearises the poses
// (omega folded into R0) so that h is taken in the chart centred at the solution. False if
// Ceres could not evaluate the problem.
bool SolveLocalBundle(int max_iterations, LocalBundleProblem* problem);

// Median depth of the observed points in their cameras (local frame units).
double MedianDepth(const LocalBundleProblem& problem);

// Unweighted RMS pixel reprojection error.
double RmsReprojectionPx(const LocalBundleProblem& problem);

}  // namespace pgba
