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
#include "pgba/optim/loss_function_options.h"
#include "pgba/optim/solver_options.h"
#include "pgba/scene/reconstruction.h"
#include "pgba/util/json_fields.h"

namespace pgba {

struct BundleAdjusterOptions {
  // Robust loss on each observation's 2-vector residual, scale in pixels (Huber: the
  // residual norm where it turns linear). Config keys "loss" ("huber", "cauchy" or
  // "trivial") and "loss_scale_px".
  LossFunctionOptions loss = {LossType::kHuber, 1.0};
  // "auto": DENSE_SCHUR up to `dense_schur_max_poses` free poses, SPARSE_SCHUR above (the
  // well-configured solver of a fair point-based baseline); or "dense_schur",
  // "sparse_schur", "iterative_schur" (SCHUR_JACOBI preconditioner) explicitly. Chosen per
  // problem: it sets solver.linear_solver_type.
  std::string linear_solver = "auto";
  int dense_schur_max_poses = 40;
  // Levenberg-Marquardt: max_iterations 100, function_tolerance 1e-6, gradient_tolerance
  // 1e-10, parameter_tolerance 1e-8; num_threads 1 (results bit-identical from run to run;
  // 0 = all hardware threads); log_progress false. Config keys: the field names.
  SolverOptions solver = [] {
    SolverOptions s;
    s.max_iterations = 100;
    return s;
  }();

  // Empty when valid, else one line naming the field and its valid range.
  std::string Check() const;
};
template <class Visit>
void JsonFields(BundleAdjusterOptions& o, Visit&& visit) {
  visit("loss", o.loss.type);
  visit("loss_scale_px", o.loss.scale);
  visit("linear_solver", o.linear_solver);
  visit("dense_schur_max_poses", o.dense_schur_max_poses);
  visit("max_iterations", o.solver.max_iterations);
  visit("function_tolerance", o.solver.function_tolerance);
  visit("gradient_tolerance", o.solver.gradient_tolerance);
  visit("parameter_tolerance", o.solver.parameter_tolerance);
  visit("num_threads", o.solver.num_threads);
  visit("log_progress", o.solver.log_progress);
}
PGBA_JSON_FROM_FIELDS(BundleAdjusterOptions)

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
// points and the free intrinsics of their cameras. Throws std::invalid_argument for options that fail Check() or a gauge
// image without observations.
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
