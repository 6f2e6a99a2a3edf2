// The radial distortion the view graph shows (for the focal estimate's sake): a fundamental
// matrix cannot explain a radial distortion, so the k1 under which the pairs' refined
// fundamental matrices leave the smallest Sampson distances is the lens's (the idea of
// Fitzgibbon, "Simultaneous linear estimation of multiple view geometry and lens
// distortion", CVPR 2001, here by a one-dimensional search instead of his quadratic
// eigenvalue problem). Without it, the focal from the singular-value gap absorbs the
// distortion: measured on the orbit scene with k1 = -0.08, focal errors of -2% to -5%
// instead of -1% (view_graph_calibration.h).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "modules/calibration/fundamental_matrix.h"
#include "pgba/scene/camera.h"

namespace pgba {

// Pixel = K * (undistorted normalised coordinates, 1): the pinhole part of a camera.
Eigen::Matrix3d PinholeMatrix(const Camera& camera);
// Pixels of `camera` undistorted onto its pinhole part (K * undistorted ray).
std::vector<Eigen::Vector2d> PinholePixels(const Camera& camera, const std::vector<Eigen::Vector2d>& pixels);
// Index of the model's first radial coefficient in Camera::params, -1 for pinhole models.
int RadialCoefficientIndex(CameraModel model);

// Correspondences of a pair of images of one camera, raw pixels, and a fundamental matrix of
// their pinhole pixels under the camera's own distortion (the refinements' start).
struct PairPixels {
  std::vector<Eigen::Vector2d> x1, x2;
  Eigen::Matrix3d F = Eigen::Matrix3d::Zero();
};

struct RadialSearchResult {
  bool searched = false;   // false: a pinhole model, or no pair
  double k1 = 0.0;         // in the camera's normalised coordinates
  double cost_at_zero = 0.0;  // sum over pairs of the truncated squared Sampson distances, px^2
  double cost = 0.0;          // ... at k1
};

// Minimises over k1 in [-max_abs_k1, max_abs_k1] (values for which the camera is not
// invertible over its image are skipped) the sum over `pairs` and their correspondences of
// min(d^2, threshold^2), d the Sampson distance under the pair's fundamental matrix refined
// (RefineFundamentalMatrix) on the pixels undistorted with k1. `camera` must have all its
// distortion coefficients 0 (k1 is then the whole distortion). Parallel over pairs (TBB),
// deterministic.
RadialSearchResult SearchRadialDistortion(const Camera& camera, const std::vector<const PairPixels*>& pairs,
                                          const FundamentalMatrixOptions& options, double max_abs_k1);

}  // namespace pgba
