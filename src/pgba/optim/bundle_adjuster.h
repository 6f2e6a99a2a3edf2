// Classical point-based bundle adjustment over a Reconstruction: poses (the shared
// PoseBlock [C, omega] parameterisation) and 3D points, pixel reprojection residuals
// (ReprojectionError) under a robust loss, solved by Ceres with a Schur complement on the
// points (points eliminated first).
//
// One adjuster serves every point-based adjustment of the project: the triplet BA (three
// views, local frame), and the point-based global BA baseline (all images, same
// initialisation and loss as the pointless adjustment). The problem description says which
// images and tracks take part and which poses are held; everything else is read from and
// written back to the Reconstruction (poses of the images, xyz of the points).
#pragma once

#include <nlohmann/json.hpp>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "pgba/optim/intrinsics.h"
#include "pgba/scene/reconstruction.h"

namespace ceres {
class LossFunction;
}

namespace pgba {

// The robust loss `name` at `scale_px` (pixels), owned by the caller: "huber", "cauchy", or
// "trivial" (nullptr: plain least squares); std::invalid_argument for another name. One
// object gives every user the cost rho(s) and the IRLS weight rho'(s) of a squared residual s
// (its Evaluate), so no caller writes the loss out by hand.
ceres::LossFunction* MakeRobustLoss(const std::string& name, double scale_px);

struct BundleAdjusterOptions {
  // Robust loss on each observation's 2-vector residual: "huber" (default), "cauchy" or
  // "trivial" (plain least squares).
  std::string loss = "huber";
  // Scale of the robust loss in pixels (Huber: residual norm where it turns linear).
  double loss_scale_px = 1.0;
  // "auto": DENSE_SCHUR up to `dense_schur_max_poses` free poses, SPARSE_SCHUR above (the
  // well-configured solver of a fair point-based baseline); or "dense_schur",
  // "sparse_schur", "iterative_schur" (SCHUR_JACOBI preconditioner) explicitly.
  std::string linear_solver = "auto";
  int dense_schur_max_poses = 40;
  // Levenberg-Marquardt stopping criteria (Ceres' meanings).
  int max_iterations = 100;
  double function_tolerance = 1e-6;
  double gradient_tolerance = 1e-10;
  double parameter_tolerance = 1e-8;
  // Ceres threads. 1 (default): results are bit-identical from run to run; with more, Ceres
  // sums the cost, gradient and Schur complement over dynamically scheduled chunks, whose
  // order changes the last bits (1e-10 in the poses). 0 = all hardware threads.
  int num_threads = 1;
  // Print Ceres' per-iteration progress to stdout.
  bool log_progress = false;
};
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(BundleAdjusterOptions, loss, loss_scale_px, linear_solver,
                                                dense_schur_max_poses, max_iterations, function_tolerance,
                                                gradient_tolerance, parameter_tolerance, num_threads, log_progress)

// State handed to the iteration callback after each accepted or rejected LM step. `state`
// is the Reconstruction being adjusted with the current poses and points written into it
// (e.g. to compute sigma per iteration).
struct BundleAdjustmentIteration {
  int iteration = 0;
  double cost = 0.0;  // Ceres cost: 0.5 * sum of robustified squared residuals
  bool step_accepted = false;
  const Reconstruction* state = nullptr;
};

// What to adjust.
struct BundleAdjustmentProblem {
  // Images whose observations take part (empty: every image). Observations in other images
  // are ignored.
  std::vector<uint32_t> image_ids;
  // Tracks (point3D ids) taking part (empty: every point of the reconstruction).
  std::vector<uint64_t> track_ids;
  // Poses held fixed (must be among the participating images to matter).
  std::vector<uint32_t> constant_pose_ids;
  // Hold every point fixed (pose-only refinement).
  bool constant_points = false;
  // Gauge of the similarity ambiguity (7 dof): if set, the pose of `gauge_anchor` is held
  // and the centre of `gauge_scale` moves on the sphere of radius |C_scale - C_anchor|
  // around C_anchor (its rotation stays free), fixing rotation, translation and scale
  // without biasing any other parameter. ChooseGauge() picks a sensible pair.
  bool fix_gauge = false;
  uint32_t gauge_anchor = 0;
  uint32_t gauge_scale = 0;
  // Self-calibration: the cameras whose parameters at these indices are estimated (shared by
  // their images) and written back to rec->cameras; every other camera is held.
  FreeIntrinsics free_intrinsics;
  std::function<void(const BundleAdjustmentIteration&)> callback;
};

struct BundleAdjustmentSummary {
  // Ceres returned a solution (converged or stopped at max_iterations).
  bool usable = false;
  // Ceres reported CONVERGENCE.
  bool converged = false;
  int iterations = 0;
  double initial_cost = 0.0;
  double final_cost = 0.0;
  double seconds = 0.0;
  int num_free_poses = 0;
  int num_points = 0;
  int num_observations = 0;
  int num_free_intrinsics = 0;  // camera parameters estimated
  std::string linear_solver;
  std::string message;  // Ceres' termination message
};
nlohmann::json ToJson(const BundleAdjustmentSummary& summary);

// Adjusts `rec` in place: poses of the free participating images, xyz of the participating
// points and the free intrinsics of their cameras. Throws std::invalid_argument for an unknown loss/solver name or a
// gauge image without observations.
BundleAdjustmentSummary BundleAdjust(const BundleAdjustmentProblem& problem, const BundleAdjusterOptions& options,
                                     Reconstruction* rec);

// Gauge pair for `image_ids` (empty: all images): the anchor is the first image, the scale
// image the one whose centre is farthest from the anchor's (largest, best-conditioned
// distance). Sets problem->fix_gauge; does nothing for fewer than two images.
void ChooseGauge(const Reconstruction& rec, BundleAdjustmentProblem* problem);

// Pixel residual norm of every observation of `point3D_id` (order of its track) at the
// current poses and point; infinity for a point behind the camera.
std::vector<double> ObservationErrorsPx(const Reconstruction& rec, uint64_t point3D_id);

// Filter step of filter-and-refine: removes the observations whose ObservationErrorsPx
// exceeds max_px (unlinking them from their image) and the points left with fewer than two;
// returns the number of observations removed.
size_t FilterObservations(double max_px, Reconstruction* rec);

}  // namespace pgba
