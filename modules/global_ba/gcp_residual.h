// The residual of one GCP seen in one triplet (paper, "Inclusion of ground control points"):
//     r_GCP = rho( || P_GCP - d_s^-1(p_GCP) ||^2 ),
// P_GCP the given coordinates (GCP frame = global frame after the frame transfer of
// gcp/gcp_alignment.h), p_GCP the GCP triangulated in the triplet's local frame from its local
// poses x0, and d_s^-1 the current local->global similarity of triplet s, i.e. the inverse
// of the centroid form of motion_similarity.h:
//     d_s(X)    = lambda alpha (X - G) + beta,
//     d_s^-1(p) = alpha^T (p - beta) / lambda + G.
// Whitened by the GCP's sigma and weighted 1 / n (gcp/gcp_constraint.h explains the choice); rho
// is a Huber loss at GcpOptions::huber_sigmas. Its only parameter block is the triplet's
// similarity [beta, theta, lambda]: the GCPs act on the poses through the triplet residuals.
#pragma once

#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include <Eigen/Core>

#include "modules/global_ba/motion_similarity.h"

namespace pgba {

// A GCP residual of one used triplet (index into the global BA's triplet terms).
struct GcpTripletTerm {
  size_t term = 0;
  int gcp = 0;                                        // index into GcpInput::gcps
  Eigen::Vector3d P = Eigen::Vector3d::Zero();        // given, global frame
  Eigen::Vector3d p_local = Eigen::Vector3d::Zero();  // triangulated with the triplet's x0
  double sigma = 1.0;                                 // metres
  double weight = 1.0;                                // 1 / (number of triplets of this GCP)
};

struct GcpResidual {
  Eigen::Vector3d P, p_local;
  double inv_sigma;
  Eigen::Matrix3d alpha0;
  Eigen::Vector3d G;

  GcpResidual(const GcpTripletTerm& t, const MotionSimilarity& sim)
      : P(t.P), p_local(t.p_local), inv_sigma(1.0 / t.sigma), alpha0(sim.alpha0), G(sim.G) {}

  // d_s^-1(p_local) at the similarity parameters `sim`.
  template <typename T>
  Eigen::Matrix<T, 3, 1> LocalToGlobal(const T* sim) const {
    Eigen::Matrix<T, 3, 3> exp_theta;
    ceres::AngleAxisToRotationMatrix(sim + 3, exp_theta.data());  // column-major, as Eigen
    const Eigen::Matrix<T, 3, 3> alpha = alpha0.cast<T>() * exp_theta;
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> beta(sim);
    return alpha.transpose() * (p_local.cast<T>() - beta) / sim[6] + G.cast<T>();
  }

  template <typename T>
  bool operator()(const T* sim, T* residual) const {
    const Eigen::Matrix<T, 3, 1> X = LocalToGlobal(sim);
    for (int i = 0; i < 3; ++i) residual[i] = (T(P(i)) - X(i)) * T(inv_sigma);
    return true;
  }

  static ceres::CostFunction* Create(const GcpResidual& r) {
    return new ceres::AutoDiffCostFunction<GcpResidual, 3, 7>(new GcpResidual(r));
  }
};

}  // namespace pgba
