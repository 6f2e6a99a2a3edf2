// The global->local similarity of a relative motion (a triplet: N = 3) as an unknown of the global BA (paper eq. 4),
// written about the triplet's centroid (ARCHITECTURE.md lesson):
//     c_k = lambda * alpha * (C_k - G) + beta,   r_k = R_k * alpha^T,
// G the centroid of the motion's initial global centres (a constant), alpha = alpha0 *
// Exp(theta). About the centroid, beta is nearly decoupled from lambda and alpha, which keeps
// the 7x7 blocks that SPARSE_SCHUR eliminates well conditioned.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "pgba/geometry/pose.h"
#include "pgba/geometry/sim3.h"

namespace pgba {

struct MotionSimilarity {
  Eigen::Matrix3d alpha0 = Eigen::Matrix3d::Identity();
  Eigen::Vector3d G = Eigen::Vector3d::Zero();
  // Parameter block: beta(3), theta(3), lambda(1).
  Eigen::Matrix<double, 7, 1> x = (Eigen::Matrix<double, 7, 1>() << 0, 0, 0, 0, 0, 0, 1).finished();

  Eigen::Matrix3d alpha() const;
  double lambda() const { return x(6); }
  Eigen::Vector3d beta() const { return x.head<3>(); }
  // The same map as a Sim3 (X_loc = s R X + t).
  Sim3 ToSim3() const;
  // Folds theta into alpha0.
  void Relinearize();
};

// Initial similarity from the motion's initial global poses and its local poses x0
// (FitMotionSimilarity, pgba/geometry/sim3.h), about the global centroid: beta is then the
// local centroid. Falls back to `fallback`'s scale when the fit has none (coincident global
// centres).
MotionSimilarity InitializeSimilarity(const std::vector<Pose>& global_poses, const std::vector<Pose>& local_poses,
                                       const Sim3& fallback);

// The given global->local similarity rewritten about the centroid G of the global centres.
MotionSimilarity SimilarityFromSim3(const std::vector<Pose>& global_poses, const Sim3& global_to_local);

}  // namespace pgba
