// RANSAC for the calibrated relative pose that scores hypotheses by the Sampson error on the
// unit spheres instead of triangulating every correspondence (OpenGV's CentralRelativePose
// SacProblem triangulates and reprojects each one for each of a hypothesis' up to 40 poses):
// a 5-point essential matrix is scored directly, ~20 flops per correspondence, and only a
// hypothesis that beats the best so far is decomposed into (R, t) and checked for cheirality.
//
// Models ranked by their outliers, then by the MSAC loss (truncated quadratic, Torr & Zisserman
// 2000) among equals, an early bail-out when a
// hypothesis' partial loss already exceeds the best one's, and the adaptive number of
// iterations of a given confidence (Fischler & Bolles) from the best inlier ratio so far.
// Deterministic for a given seed.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

namespace pgba {

struct EssentialRansacOptions {
  // Inlier threshold on |SampsonAngle| (radians), the same test Classify applies afterwards.
  double threshold_angle = 1e-3;
  // Minimal solver: "stewenius" or "nister" (OpenGV's 5-point solvers).
  std::string algorithm = "stewenius";
  // Hypotheses at most, and the confidence of having drawn at least one all-inlier sample
  // after which sampling stops (the iteration count adapts to the best inlier ratio).
  int max_iterations = 2000;
  double confidence = 0.9999;
  // Never fewer hypotheses than this: a lucky early sample with a high inlier ratio would
  // otherwise stop after a handful, leaving the best of a few to the refinement.
  int min_iterations = 20;
  uint64_t seed = 0;
  // Empty when valid, else one line naming the first field out of its valid range (the
  // ranges of io/option_ranges.cc) or breaking a rule between fields.
  std::string Check() const;
};

struct EssentialRansacResult {
  bool success = false;
  // x_2 = R_21 x_1 + t_21, |t_21| = 1: of the four decompositions of the best E, the one
  // with the most of its inliers in front of both cameras.
  Eigen::Matrix3d R_21 = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t_21 = Eigen::Vector3d::UnitX();
  Eigen::Matrix3d E_21 = Eigen::Matrix3d::Zero();  // b2^T E_21 b1 = 0
  int num_inliers = 0;  // of E under the threshold and in front of both cameras
  int iterations = 0;
};

// Squared Sampson angle of b1 <-> b2 under any E_21 (scale-free; unit bearings).
inline double SampsonAngleSquared(const Eigen::Matrix3d& E_21, const Eigen::Vector3d& b1, const Eigen::Vector3d& b2) {
  const Eigen::Vector3d Eb1 = E_21 * b1;
  const Eigen::Vector3d Etb2 = E_21.transpose() * b2;
  const double g = b2.dot(Eb1);
  const double denom = Eb1.squaredNorm() + Etb2.squaredNorm() - 2.0 * g * g;
  return denom > 1e-300 ? g * g / denom : 0.0;
}

// Needs at least 5 correspondences; throws std::invalid_argument for an unknown algorithm.
EssentialRansacResult EssentialRansac(const std::vector<Eigen::Vector3d>& b1, const std::vector<Eigen::Vector3d>& b2,
                                      const EssentialRansacOptions& options);

}  // namespace pgba
