// Focal lengths from the view graph, before rotation averaging (the idea of GLOMAP's
// ViewGraphCalibrator, Pan et al., "Global Structure-from-Motion Revisited", ECCV 2024, sec.
// 3.1): for the right intrinsics K1, K2 the essential matrix E = K2^T F K1 of a pair's
// fundamental matrix F has two equal non-zero singular values (Hartley & Zisserman, result
// 9.19), so each camera's focal is the one that minimises, over its verified pairs, the
// robust squared gap
//     r^2 = ((s1 - s2) / (s1 + s2))^2 = (T - 2 sqrt(D)) / (T + 2 sqrt(D)),            (1)
// T = |E|_F^2 = s1^2 + s2^2, D = sum of the squared 2x2 minors of E = s1^2 s2^2 (E has rank
// 2, so these are the coefficients of its characteristic polynomial: no SVD is needed).
// Cost of camera c: sum over its pairs of the Cauchy loss rho(r^2) = a^2 log(1 + r^2 / a^2).
//
// One unknown per camera (shared by its images): the factor s by which its focal(s) scale;
// the principal point stays where the prior put it (the image centre) and the distortion as
// given. The cost is minimised over log s by a grid over [min_focal_ratio, max_focal_ratio]
// x the prior and a golden-section search around the best node (no local minimum trap, no
// derivative of (1) needed), one camera at a time with the others fixed, for a few sweeps.
//
// The focal is not observable when the optical axes of every pair are parallel or meet at a
// point equidistant from the two centres (Sturm, "On focal length calibration from two
// views", CVPR 2001): nadir blocks, rings around an object. The cost is then flat; the
// standard deviation of log s from its curvature (Gauss-Newton: var = 2 sigma^2 / C'', sigma^2
// = C / (n - 1)) tells, and an estimate less precise than max_relative_sd keeps the prior.
#pragma once

#include <nlohmann/json.hpp>

#include <Eigen/Core>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "modules/calibration/fundamental_matrix.h"
#include "pgba/scene/reconstruction.h"
#include "pgba/scene/view_graph.h"

namespace pgba {

// Which cameras get their focal estimated.
enum class FocalEstimationCameras {
  kWeakPrior,  // those without a prior focal (Camera::has_prior_focal_length false)
  kAll,        // every camera (a prior focal from a file or EXIF is only the start)
  kNone,       // none: the step is skipped
};
NLOHMANN_JSON_SERIALIZE_ENUM(FocalEstimationCameras, {{FocalEstimationCameras::kWeakPrior, "weak_prior"},
                                                      {FocalEstimationCameras::kAll, "all"},
                                                      {FocalEstimationCameras::kNone, "none"}})

struct ViewGraphCalibrationOptions {
  FocalEstimationCameras cameras = FocalEstimationCameras::kWeakPrior;
  FundamentalMatrixOptions fundamental;
  // Scale a of the Cauchy loss on r^2 (1), in units of r: pairs whose gap exceeds ~a (a wrong
  // F, a degenerate pair) count little. Measured (focal error, loss 0.01 / 0.02 / 0.05):
  // fountain_p11 -1.4% / -1.8% / -4.2%, herzjesu_p8 +1.4 / +1.1 / -, orbit k1 -0.08 within
  // 1.7 / 2.0 / 2.1%, aerial (nadir, near-degenerate) +4.7..5.2 / +2.8..4.0 / +1.1..2.9%.
  double loss_scale = 0.01;
  // Search interval of the focal, as factors of the prior focal.
  double min_focal_ratio = 0.25;
  double max_focal_ratio = 4.0;
  // A camera needs at least this many pairs with a fundamental matrix.
  int min_pairs = 3;
  // The estimate replaces the prior only if the standard deviation of its log (~ relative
  // standard deviation of the focal) is at most this.
  double max_relative_sd = 0.05;
  // Rounds of one-camera-at-a-time minimisation when several cameras are estimated.
  int max_sweeps = 5;
  // Estimate the radial k1 of the distortion-free cameras with a radial coefficient
  // (SIMPLE_RADIAL, RADIAL, OPENCV) from their pairs first (radial_distortion_search.h),
  // searched in [-max_abs_k1, max_abs_k1] (normalised coordinates of the prior focal); the
  // camera gets it with its focal.
  bool estimate_k1 = true;
  double max_abs_k1 = 0.3;
  // Pairs used per camera at most, those with the most fundamental-matrix inliers first
  // (bounds the work on large sets; 0 = all).
  int max_pairs_per_camera = 400;
  // A pair is left out when a homography explains at least this fraction of its fundamental
  // matrix's inliers (a planar scene or a pure rotation: no unique F, so no focal; COLMAP's
  // max_H_inlier_ratio). Measured on the synthetic planar scenes (a textured plane, 15% long
  // prior): without the test seeds 3 and 4 took 1496 and 1742 px for 726 (relative sd 0.03-0.04,
  // "determined"), and the global BA could not recover (30/60 registered, or a solver failure).
  // >= 1: every pair is used.
  double max_homography_inlier_ratio = 0.8;
  // `pgba run` only: the matches are verified with the cameras as they are before any
  // adjustment, so with a prior far off (15% focal, k1 -0.08: ~20 px at the corners) the
  // two-view verification drops correct matches at the image borders, where focal and
  // distortion show most. When self-calibration moved some pixel of a camera by more than this
  // (pixel_shift.h), the images are matched again with the refined cameras and reconstructed
  // once more from them. Measured on rendered photos (synth --render --k1 -0.08
  // --focal-prior-error 0.15, seed 2): relative rotation error 1.83x -> 1.12x of the true
  // calibration held. Default 1 px: half the verification threshold. 0 = never.
  double rematch_shift_px = 1.0;
  // Empty if usable, else the first problem naming the key.
  std::string Check() const;
};
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(ViewGraphCalibrationOptions, cameras, fundamental, loss_scale,
                                                min_focal_ratio, max_focal_ratio, min_pairs, max_relative_sd,
                                                max_sweeps, estimate_k1, max_abs_k1, max_pairs_per_camera,
                                                max_homography_inlier_ratio, rematch_shift_px)

struct CameraFocalEstimate {
  uint32_t camera_id = 0;
  double prior_focal = 0.0;      // Camera::MeanFocal before
  double estimated_focal = 0.0;  // the minimiser of the cost (whether applied or not)
  double relative_sd = 0.0;      // standard deviation of log(focal) (infinity if flat)
  int pairs_used = 0;            // pairs with a fundamental matrix touching the camera
  double rms_gap_prior = 0.0;    // RMS of r (1) over its pairs at the prior focal
  double rms_gap_estimate = 0.0;  // ... at the estimate
  bool k1_searched = false;      // a k1 was found (it lowered the pairs' Sampson cost)
  double estimated_k1 = 0.0;     // with the estimated focal (applied with it)
  double sampson_cost_ratio = 1.0;  // the pairs' Sampson cost with k1 / without
  bool applied = false;          // the camera now has the estimated focal (and k1)
  std::string reason;            // why not applied (empty if applied)
};

struct ViewGraphCalibrationResult {
  std::vector<CameraFocalEstimate> cameras;  // the cameras considered, by id
  int pairs_considered = 0;                  // verified pairs touching an estimated camera
  int pairs_with_fundamental = 0;
  int pairs_planar = 0;  // left out: a homography explains them (max_homography_inlier_ratio)
  double seconds = 0.0;
  bool AnyApplied() const;
  nlohmann::json ToJson() const;
};

// Estimates the focals of the cameras of `cameras` selected by options.cameras from the
// verified `pairs` of `tracks` (pixels of the shared tracks, undistorted with the current
// camera), and scales the focal(s) of those with a usable estimate in place. Pairs are
// processed in parallel (TBB) into per-pair slots: the result does not depend on the thread
// count. std::invalid_argument for options that fail Check().
ViewGraphCalibrationResult CalibrateFocalsFromViewGraph(const Reconstruction& tracks,
                                                        const std::vector<TwoViewGeometry>& pairs,
                                                        const ViewGraphCalibrationOptions& options,
                                                        std::map<uint32_t, Camera>* cameras);

// r^2 of (1) for E = K2^T F K1 (K from each camera's focal(s) and principal point).
double SingularValueGapSquared(const Eigen::Matrix3d& F, const Camera& camera1, const Camera& camera2);

// `camera` with its focal(s) multiplied by `scale` (principal point and distortion kept).
Camera ScaleFocal(const Camera& camera, double scale);

}  // namespace pgba
