// The residual of one relative motion of N views in the global BA (paper eq. 5, with the
// gradient term of eq. 3):
//     r_s = W_s (x_s(X, sim_s) - x0_s - n_s),     W_s^T W_s = h_s  (W_s = D_s V_s),
// n_s = -h_s^-1 g_s the Newton step of the local quadratic at x0_s (LocalHessian::newton_step;
// zero for a converged local BA, as eq. 5 assumes),
// x_s stacking, for the motion's views k = 0..N-1, the local 6-vector predicted from the
// global pose through the similarity (paper eq. 4, centroid form of motion_similarity.h),
// in the SAME chart as h_s around the local BA's solution x0 = {r0_k, c0_k}:
//     [ c_k - c0_k ;  Log(r0_k^T r_k) ],   c_k = lambda alpha (C_k - G) + beta,
//                                          r_k = R0_k Exp(omega_k) alpha^T.
// Parameter blocks: the N global poses [C, omega] (pose_parameterization.h) and the
// similarity [beta, theta, lambda]; with self-calibration (paper, "Self-calibrating bundle
// adjustment") also the global intrinsic unknowns of each camera of h (LocalHessian::
// intrinsic_camera_ids), whose deviation kappa_c - kappa0_c follows the 6N pose rows (the
// local frame does not act on intrinsics, so they are compared directly).
//
// The Jacobian is composed, not differentiated through W: each view's 6-vector depends only
// on its own pose and the similarity, so its 6 x 13 Jacobian is written per view in closed
// form (ViewDeviation::Linearize), and W_s multiplies those blocks in doubles. A motion of N
// views costs O(N^2) multiplications, not O(N^3) Jet operations.
#pragma once

#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include <Eigen/Core>
#include <memory>
#include <vector>

#include "modules/global_ba/motion_similarity.h"
#include "modules/global_ba/motion_weight.h"
#include "modules/local_hessian/local_hessian.h"

namespace pgba {

// One view's deviation [c_k - c0_k ; Log(r0_k^T r_k)] as a function of its global pose block
// and the similarity block.
struct ViewDeviation {
  Eigen::Matrix3d alpha0;
  Eigen::Vector3d G;
  Eigen::Matrix3d r0t_R0;  // r0_k^T R0_k (R0_k: reference rotation of the global pose block)
  Eigen::Vector3d c0;

  template <typename T>
  void operator()(const T* pose, const T* sim, T* dx) const {
    using Mat3 = Eigen::Matrix<T, 3, 3>;
    Mat3 exp_theta;
    ceres::AngleAxisToRotationMatrix(sim + 3, exp_theta.data());  // column-major, as Eigen
    const Mat3 alpha = alpha0.cast<T>() * exp_theta;
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> beta(sim);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> C(pose);
    Eigen::Map<Eigen::Matrix<T, 3, 1>> dc(dx);
    dc = sim[6] * (alpha * (C - G.cast<T>())) + beta - c0.cast<T>();
    Mat3 exp_omega;
    ceres::AngleAxisToRotationMatrix(pose + 3, exp_omega.data());
    const Mat3 d = r0t_R0.cast<T>() * exp_omega * alpha.transpose();
    ceres::RotationMatrixToAngleAxis(d.data(), dx + 3);  // quaternion/atan2 based: exact near 0
  }

  // dx (as operator()) and its 6 x 13 Jacobian d dx / d(pose, sim), in closed form (SO(3) right
  // Jacobians, motion_residual.cc); the templated operator() is its reference in the tests.
  void Linearize(const double* pose, const double* sim, double* dx, Eigen::Matrix<double, 6, 13>* J) const;
};

class MotionResidual : public ceres::CostFunction {
 public:
  // R0: reference rotations of the N global pose blocks; x0: the motion's local poses.
  // `intrinsics0` (K values) and `intrinsic_sizes` (per camera, summing to K): the intrinsic
  // rows of h; W is then (6N + K) square. W is factored and shared, not copied (motion_weight.h):
  // the global BA makes a residual per motion for every round and fitting error.
  MotionResidual(const std::vector<Eigen::Matrix3d>& R0, const MotionSimilarity& sim, const std::vector<Pose>& x0,
                 MotionWeight W, const Eigen::VectorXd& newton_step = Eigen::VectorXd(),
                 const Eigen::VectorXd& intrinsics0 = Eigen::VectorXd(), const std::vector<int>& intrinsic_sizes = {});
  MotionResidual(const std::vector<Eigen::Matrix3d>& R0, const MotionSimilarity& sim, const std::vector<Pose>& x0,
                 const Eigen::MatrixXd& W, const Eigen::VectorXd& newton_step = Eigen::VectorXd(),
                 const Eigen::VectorXd& intrinsics0 = Eigen::VectorXd(), const std::vector<int>& intrinsic_sizes = {})
      : MotionResidual(R0, sim, x0, MotionWeight::Dense(W), newton_step, intrinsics0, intrinsic_sizes) {}

  int num_views() const { return static_cast<int>(views_.size()); }
  int num_intrinsics() const { return static_cast<int>(intrinsics0_.size()); }
  const std::vector<int>& intrinsic_sizes() const { return intrinsic_sizes_; }

  // r_s at the given blocks (poses[k]: 6 doubles of view k; sim: 7; intrinsics[c]: the free
  // values of camera c of h). Needs a factored W (motion_weight.h).
  Eigen::VectorXd Evaluate(const std::vector<const double*>& poses, const double* sim,
                           const std::vector<const double*>& intrinsics = {}) const;
  // |r_s|^2 at the given blocks, with any form of W.
  double SquaredNorm(const std::vector<const double*>& poses, const double* sim,
                     const std::vector<const double*>& intrinsics = {}) const;
  // The gradient of 1/2 |r_s|^2 with respect to the deviation dx = x_s - x0_s: W^T r_s.
  Eigen::VectorXd DeviationGradient(const Eigen::VectorXd& dx) const;

  // Ceres: blocks poses[0..N-1], sim, intrinsics[0..C-1]; residuals 6N + K. Needs a factored W.
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

  // x_s - x0_s (before the weight matrix), for tests of the chart.
  Eigen::VectorXd Deviation(const std::vector<const double*>& poses, const double* sim,
                            const std::vector<const double*>& intrinsics = {}) const;

  // The deviation x_s - x0_s and its Jacobian, view by view: J[k] = d dx_k / d(pose_k, sim),
  // 6 x 13 (pose block first); the intrinsic rows of dx have the identity as Jacobian. The
  // weighted residual is W dx - offset.
  void Linearize(const std::vector<const double*>& poses, const double* sim,
                 const std::vector<const double*>& intrinsics, Eigen::VectorXd* dx,
                 std::vector<Eigen::Matrix<double, 6, 13>>* J) const;
  const MotionWeight& W() const { return W_; }

 private:
  // kappa_c - kappa0_c for every camera, concatenated (K values).
  void IntrinsicDeviation(const std::vector<const double*>& intrinsics, double* out) const;

  std::vector<ViewDeviation> views_;
  MotionWeight W_;
  Eigen::VectorXd newton_step_;  // n_s (zero when none was given)
  Eigen::VectorXd offset_;       // W_s n_s (a factored W only)
  Eigen::VectorXd intrinsics0_;
  std::vector<int> intrinsic_sizes_;
};

}  // namespace pgba
