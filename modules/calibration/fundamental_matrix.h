// Uncalibrated two-view geometry: the fundamental matrix x2^T F x1 = 0 of pixel
// correspondences (Hartley & Zisserman, Multiple View Geometry, 2nd ed., ch. 11), for
// estimating focal lengths the calibration does not give (view_graph_calibration.h).
//
// RANSAC over OpenCV's 7-point solver (cv::findFundamentalMat, FM_RANSAC: deterministic,
// its sampler has a fixed seed), then a refinement on the inliers: the normalised 8-point
// algorithm (H&Z alg. 11.1) reweighted iteratively by the Sampson denominator (H&Z eq.
// 11.9), so that the algebraic residuals it minimises become Sampson distances, with a Huber
// weight against the inliers that are not.
#pragma once

#include <nlohmann/json.hpp>

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

namespace pgba {

struct FundamentalMatrixOptions {
  // RANSAC inlier threshold on the Sampson distance, pixels. Larger than a calibrated
  // threshold: the pixels still carry the lens distortion the prior does not model.
  double threshold_px = 3.0;
  // RANSAC confidence of having drawn an all-inlier sample, in (0, 1).
  double confidence = 0.999;
  // RANSAC hypotheses at most.
  int max_iterations = 2000;
  // Below this many inliers the pair gives no fundamental matrix (>= 8: the refinement's
  // minimum).
  int min_inliers = 30;
  // Reweighted 8-point iterations on the inliers (0 = keep the RANSAC model).
  int refine_iterations = 10;
  // Huber threshold of the refinement's weights, pixels (Sampson distance).
  double huber_px = 1.0;
  // Empty if usable, else the first problem naming the key.
  std::string Check() const;
};
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(FundamentalMatrixOptions, threshold_px, confidence, max_iterations,
                                                min_inliers, refine_iterations, huber_px)

struct FundamentalMatrixResult {
  bool success = false;
  Eigen::Matrix3d F = Eigen::Matrix3d::Zero();  // x2^T F x1 = 0, rank 2, |F|_Frobenius = 1
  std::vector<uint8_t> inlier_mask;             // per correspondence, Sampson distance <= threshold
  int num_inliers = 0;
  double rms_sampson_px = 0.0;  // over the inliers, after refinement
};

// F from pixel correspondences x1[i] <-> x2[i] (undistorted as far as the caller knows).
// std::invalid_argument for mismatched sizes; success = false with fewer than
// max(8, min_inliers) correspondences or inliers.
FundamentalMatrixResult EstimateFundamentalMatrix(const std::vector<Eigen::Vector2d>& x1,
                                                  const std::vector<Eigen::Vector2d>& x2,
                                                  const FundamentalMatrixOptions& options);

// The refinement alone, from `initial` (any F of the pair): inliers of `initial` at the
// threshold, then the reweighted 8-point iterations (inliers re-marked after each). What
// EstimateFundamentalMatrix runs after its RANSAC; success = false below min_inliers.
FundamentalMatrixResult RefineFundamentalMatrix(const std::vector<Eigen::Vector2d>& x1,
                                                const std::vector<Eigen::Vector2d>& x2, const Eigen::Matrix3d& initial,
                                                const FundamentalMatrixOptions& options);

// First-order geometric distance of x1 <-> x2 to the epipolar constraint, pixels (H&Z 11.9).
double SampsonDistance(const Eigen::Matrix3d& F, const Eigen::Vector2d& x1, const Eigen::Vector2d& x2);

}  // namespace pgba
