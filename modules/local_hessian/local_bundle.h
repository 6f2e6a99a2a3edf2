// The local bundle adjustment of one relative motion (paper eq. 1) in the motion's frame: its
// N poses (PoseBlock, the shared [C, omega] chart), its points triangulated from the local
// poses, and the observations of those points in the N views.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "modules/local_hessian/local_hessian.h"
#include "pgba/optim/pose_parameterization.h"

namespace pgba {

struct LocalObservation {
  int view = 0;   // 0..N-1, position in LocalMotion::image_ids
  int point = 0;  // index into LocalBundleProblem::points
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();
  // Relative weight of this observation's squared residual (times observation_weight).
  double weight = 1.0;
};

struct LocalBundleProblem {
  std::vector<PoseBlock> poses;
  std::vector<const Camera*> cameras;
  std::vector<Eigen::Vector3d> points;
  // Grouped by point (all observations of point i are contiguous, in view order).
  std::vector<LocalObservation> observations;
  // Weight of each squared residual: gamma / M (paper's attenuation), 1 if disabled.
  double observation_weight = 1.0;
  double huber_px = 1.0;
  // Optional pose prior of the local BA (PriorPlacement::kLocalBAAndHessian): cost
  // 1/2 (x - x_in)^T prior (x - x_in) over the stacked 6N-vector of the pose blocks,
  // centred at the input poses (empty: none).
  Eigen::MatrixXd prior;
  Eigen::VectorXd prior_center;
  // Observations of the motion's tracks in its views before the gross-outlier filter (those
  // of tracks that failed to triangulate included): the denominator of RobustCost.
  int num_candidate_observations = 0;
  double max_reprojection_px = 4.0;

  int num_views() const { return static_cast<int>(poses.size()); }
};

// The motion's robust reprojection cost at its current poses and points: Huber (huber_px) of
// every kept observation's pixel error, and the Huber cost of max_reprojection_px for every
// candidate observation the filter dropped, so that costs at different poses compare over the
// same observations (the damped re-linearisation of the global BA accepts a step by it).
double RobustCost(const LocalBundleProblem& problem);

// gamma / M with gamma = M Q / (M + Q) (paper, implementation details); 1 for Q <= 0 or inf.
double AttenuationWeight(int num_points, double q);

// Collects the motion's tracks from the tracks model, triangulates each from the local poses
// (TriangulateTrack), drops gross outlier observations and points with < 2 views. Returns
// kOk, kInvalidInput or kTooFewPoints.
LocalHessianStatus BuildLocalBundleProblem(const Reconstruction& tracks, const LocalMotion& motion,
                                           const LocalHessianOptions& options, LocalBundleProblem* problem,
                                           const ObservationShares* shares = nullptr);

// Runs `max_iterations` Levenberg-Marquardt iterations (Ceres, DENSE_SCHUR, single thread:
// motions are parallelised outside) on poses and points, then re-linearises the poses
// (omega folded into R0) so that h is taken in the chart centred at the solution. False if
// Ceres could not evaluate the problem.
// With `fix_gauge` the first pose and the largest baseline coordinate of the second are held
// (a BA that must converge from afar, local_motions.h; the local Hessian's single step runs
// gauge-free instead, so that h is the plain normal matrix).
bool SolveLocalBundle(int max_iterations, LocalBundleProblem* problem, bool fix_gauge = false);

// Median depth of the observed points in their cameras (local frame units).
double MedianDepth(const LocalBundleProblem& problem);

// Unweighted RMS pixel reprojection error.
double RmsReprojectionPx(const LocalBundleProblem& problem);

}  // namespace pgba
