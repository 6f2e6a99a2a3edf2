// Calibrated relative pose of two views from bearing correspondences: OpenGV's 5-point
// solver (Stewenius or Nister) in OpenGV's RANSAC, then a robust nonlinear refinement of
// the Sampson error on the inliers, and a cheirality check.
//
// General API shared by the view graph of the tracks pipeline (modules/triplets) and the
// geometric verification of the image front end: inputs are undistorted unit bearings
// (Camera::PixelToBearing), a pixel threshold and the focal length that converts it to an
// angle.
#pragma once

#include <nlohmann/json.hpp>

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "pgba/optim/loss_function_options.h"
#include "pgba/optim/solver_options.h"
#include "pgba/util/json_fields.h"

namespace pgba {

struct RelativePoseOptions {
  // Inlier threshold on the reprojection error, pixels. It is converted to an angle with
  // the focal length (theta = atan(threshold_px / focal_px)); OpenGV's RANSAC scores a
  // correspondence by the sum over both views of 1 - cos(angle to the reprojected
  // triangulated point), compared with 1 - cos(theta).
  double threshold_px = 2.0;
  // Minimal solver: "stewenius" or "nister" (OpenGV, 5 points + 3 to disambiguate).
  std::string algorithm = "stewenius";
  // How RANSAC scores a hypothesis: "sampson" (essential_ransac.h: the Sampson angle of the
  // 5-point E, MSAC loss with bail-out and local optimisation, cheirality of the final model
  // only) or "opengv" (OpenGV's CentralRelativePoseSacProblem: each correspondence
  // triangulated and reprojected for every hypothesis). The front end's verification uses
  // "sampson" (DefaultVerificationPoseOptions); the view graph of the tracks pipeline keeps
  // "opengv" for now: its tests pin values of it (GlobalMapper.Planar* expect an
  // inconsistent pair that Sampson scoring no longer produces).
  std::string scoring = "opengv";
  // RANSAC limits: hypotheses and the confidence of having drawn one all-inlier sample.
  int max_iterations = 2000;
  double confidence = 0.9999;
  // Seed of RANSAC's sampling (results are deterministic for a given seed).
  uint64_t seed = 0;
  // Nonlinear refinement of the Sampson error on the inliers: Huber loss at 1 px (config
  // key "huber_px"), Ceres' dense QR, at most 50 iterations, one thread.
  bool refine = true;
  LossFunctionOptions loss = {LossType::kHuber, 1.0};
  SolverOptions solver = [] {
    SolverOptions s;
    s.linear_solver_type = ceres::DENSE_QR;
    return s;
  }();
  // Refine + re-classify passes after RANSAC, stopping early (when `refine_until_converged`)
  // once a pass leaves the inliers unchanged and turns the rotation by less than 1e-4 deg.
  // Two fixed passes were enough from OpenGV's hypotheses; from the Sampson-scored ones they
  // were not (entry_p10: the same inliers, median pair rotation error 0.056 vs 0.039 deg, max
  // 0.40 vs 0.27 deg), and up to 6 until converged give 0.038 / 0.150 deg.
  int refine_passes = 2;
  bool refine_until_converged = false;
  // The refinement uses at most this many inliers, evenly spaced (a few hundred already
  // pin the pose far below the pixel noise; this keeps dense pairs cheap).
  int max_refine_correspondences = 1000;
  // Below this many inliers the estimate is a failure.
  int min_inliers = 15;
  // Empty when valid, else one line naming the first field out of its valid range (the
  // ranges of io/option_ranges.cc) or breaking a rule between fields.
  std::string Check() const;
};
template <class Visit>
void JsonFields(RelativePoseOptions& o, Visit&& visit) {
  visit("threshold_px", o.threshold_px);
  visit("algorithm", o.algorithm);
  visit("scoring", o.scoring);
  visit("max_iterations", o.max_iterations);
  visit("confidence", o.confidence);
  visit("seed", o.seed);
  visit("refine", o.refine);
  visit("huber_px", o.loss.scale);
  visit("refine_passes", o.refine_passes);
  visit("refine_until_converged", o.refine_until_converged);
  visit("max_refine_correspondences", o.max_refine_correspondences);
  visit("min_inliers", o.min_inliers);
}
PGBA_JSON_FROM_FIELDS(RelativePoseOptions)

struct RelativePoseResult {
  bool success = false;
  // x_2 = R_21 x_1 + t_21 (camera frames), |t_21| = 1. The centre of view 2 in view 1's
  // frame is -R_21^T t_21.
  Eigen::Matrix3d R_21 = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t_21 = Eigen::Vector3d::UnitX();
  // One entry per correspondence: 1 if it is an inlier (Sampson error below the threshold
  // and in front of both cameras).
  std::vector<uint8_t> inlier_mask;
  int num_inliers = 0;
  // Median over the inliers of the angle between the two viewing rays (R_21 b1 vs b2),
  // i.e. the triangulation angle: ~0 for a pure rotation or a baseline tiny w.r.t. depth.
  double median_triangulation_angle_deg = 0.0;
  int ransac_iterations = 0;
  // Standard deviation of the rotation, degrees, along its worst-determined axis: first-order
  // covariance of the Sampson residuals at the inliers' own noise level (infinity when the
  // fit is singular). Large when rotation and translation trade off (a small or planar patch
  // of matches).
  double rotation_sd_deg = 0.0;
};

// Estimates the relative pose from unit bearings b1[i] <-> b2[i] (camera frames).
// `focal_px` converts options.threshold_px to an angle (for two different cameras, their
// mean focal). Throws std::invalid_argument for mismatched sizes, a non-positive focal or
// an unknown algorithm; returns success = false when too few correspondences or inliers.
RelativePoseResult EstimateRelativePose(const std::vector<Eigen::Vector3d>& bearings1,
                                        const std::vector<Eigen::Vector3d>& bearings2, double focal_px,
                                        const RelativePoseOptions& options);

// The same inlier classification, refinement passes and statistics as EstimateRelativePose,
// from a given pose instead of RANSAC's (a pose verified earlier on other correspondences
// of the same pair, e.g. the front end's on its matches, refined on the tracks'). The
// threshold, refinement and min_inliers options apply; the RANSAC ones are unused
// (ransac_iterations stays 0). std::invalid_argument as EstimateRelativePose, and for a
// non-finite or zero starting pose.
RelativePoseResult RefineRelativePose(const std::vector<Eigen::Vector3d>& bearings1,
                                      const std::vector<Eigen::Vector3d>& bearings2, double focal_px,
                                      const RelativePoseOptions& options, const Eigen::Matrix3d& R_21,
                                      const Eigen::Vector3d& t_21);

// Sampson approximation of the reprojection error of b1 <-> b2 under (R_21, t_21), as an
// angle in radians (first-order distance on the two unit spheres to the epipolar
// constraint b2^T [t]x R b1 = 0).
double SampsonAngle(const Eigen::Matrix3d& R_21, const Eigen::Vector3d& t_21, const Eigen::Vector3d& b1,
                    const Eigen::Vector3d& b2);

// True if the point triangulated from b1 <-> b2 lies in front of both cameras (or the rays
// are parallel to within `parallel_angle_rad`, a point at infinity whose depth sign is
// undetermined).
bool InFrontOfBoth(const Eigen::Matrix3d& R_21, const Eigen::Vector3d& t_21, const Eigen::Vector3d& b1,
                   const Eigen::Vector3d& b2, double parallel_angle_rad);

}  // namespace pgba
