// The residual of one triplet in the global BA (paper eq. 5, with the gradient term of eq. 3):
//     r_s = W_s (x_s(X, sim_s) - x0_s - n_s),     W_s^T W_s = h_s  (W_s = D_s V_s),
// n_s = -h_s^-1 g_s the Newton step of the local quadratic at x0_s (LocalHessian::newton_step;
// zero for a converged local BA, as eq. 5 assumes),
// x_s stacking, for the triplet's views k = 0..2, the local 6-vector predicted from the
// global pose through the similarity (paper eq. 4, centroid form of triplet_similarity.h),
// in the SAME chart as h_s around the local BA's solution x0 = {r0_k, c0_k}:
//     [ c_k - c0_k ;  Log(r0_k^T r_k) ],   c_k = lambda alpha (C_k - G) + beta,
//                                          r_k = R0_k Exp(omega_k) alpha^T.
// Parameter blocks: the three global poses [C, omega] (pose_parameterization.h) and the
// similarity [beta, theta, lambda].
#pragma once

#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include <Eigen/Core>
#include <array>

#include "modules/global_ba/triplet_similarity.h"
#include "modules/local_hessian/local_hessian.h"

namespace pgba {

struct TripletMotionResidual {
  // The similarity's alpha0 and G, r0_k^T R0_k (R0_k: reference rotation of global pose
  // block k), c0_k, and W_s.
  Eigen::Matrix3d alpha0;
  Eigen::Vector3d G;
  std::array<Eigen::Matrix3d, 3> r0t_R0;
  std::array<Eigen::Vector3d, 3> c0;
  Matrix18d W;
  Vector18d offset = Vector18d::Zero();  // W_s n_s

  TripletMotionResidual(const std::array<Eigen::Matrix3d, 3>& R0, const TripletSimilarity& sim,
                        const std::array<Pose, 3>& x0, const Matrix18d& W,
                        const Vector18d& newton_step = Vector18d::Zero())
      : alpha0(sim.alpha0), G(sim.G), W(W), offset(W * newton_step) {
    for (int k = 0; k < 3; ++k) {
      r0t_R0[k] = x0[k].R().transpose() * R0[k];
      c0[k] = x0[k].C();
    }
  }

  // x_s - x0_s in h's chart (before the weight matrix).
  template <typename T>
  void Deviation(const T* const poses[3], const T* sim, Eigen::Matrix<T, 18, 1>* dx) const {
    using Mat3 = Eigen::Matrix<T, 3, 3>;
    Mat3 exp_theta;
    ceres::AngleAxisToRotationMatrix(sim + 3, exp_theta.data());  // column-major, as Eigen
    const Mat3 alpha = alpha0.cast<T>() * exp_theta;
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> beta(sim);
    const T& lambda = sim[6];
    for (int k = 0; k < 3; ++k) {
      const Eigen::Map<const Eigen::Matrix<T, 3, 1>> C(poses[k]);
      dx->template segment<3>(6 * k) = lambda * (alpha * (C - G.cast<T>())) + beta - c0[k].cast<T>();
      Mat3 exp_omega;
      ceres::AngleAxisToRotationMatrix(poses[k] + 3, exp_omega.data());
      const Mat3 d = r0t_R0[k].cast<T>() * exp_omega * alpha.transpose();
      T log_d[3];
      ceres::RotationMatrixToAngleAxis(d.data(), log_d);  // quaternion/atan2 based: exact near 0
      for (int i = 0; i < 3; ++i) (*dx)(6 * k + 3 + i) = log_d[i];
    }
  }

  template <typename T>
  bool operator()(const T* p0, const T* p1, const T* p2, const T* sim, T* residual) const {
    const T* const poses[3] = {p0, p1, p2};
    Eigen::Matrix<T, 18, 1> dx;
    Deviation(poses, sim, &dx);
    // W dx - W n with double coefficients (no 18x18 matrix of Jets).
    for (int i = 0; i < 18; ++i) {
      residual[i] = W(i, 0) * dx(0) - T(offset(i));
      for (int j = 1; j < 18; ++j) residual[i] += W(i, j) * dx(j);
    }
    return true;
  }

  static ceres::CostFunction* Create(const TripletMotionResidual& residual) {
    return new ceres::AutoDiffCostFunction<TripletMotionResidual, 18, 6, 6, 6, 7>(new TripletMotionResidual(residual));
  }
};

}  // namespace pgba
