#include "modules/global_ba/motion_residual.h"

#include <ceres/jet.h>

namespace pgba {

namespace {
constexpr int kVars = 6 + 7;  // one pose block and the similarity
using Jet13 = ceres::Jet<double, kVars>;
}  // namespace

MotionResidual::MotionResidual(const std::vector<Eigen::Matrix3d>& R0, const MotionSimilarity& sim,
                               const std::vector<Pose>& x0, const Eigen::MatrixXd& W,
                               const Eigen::VectorXd& newton_step)
    : W_(W) {
  const int n = static_cast<int>(x0.size());
  for (int k = 0; k < n; ++k) views_.push_back({sim.alpha0, sim.G, x0[k].R().transpose() * R0[k], x0[k].C()});
  offset_ = newton_step.size() == 6 * n ? Eigen::VectorXd(W * newton_step) : Eigen::VectorXd::Zero(6 * n);
  set_num_residuals(6 * n);
  for (int k = 0; k < n; ++k) mutable_parameter_block_sizes()->push_back(6);
  mutable_parameter_block_sizes()->push_back(7);
}

Eigen::VectorXd MotionResidual::Deviation(const std::vector<const double*>& poses, const double* sim) const {
  Eigen::VectorXd dx(6 * num_views());
  for (int k = 0; k < num_views(); ++k) views_[k](poses[k], sim, dx.data() + 6 * k);
  return dx;
}

Eigen::VectorXd MotionResidual::Evaluate(const std::vector<const double*>& poses, const double* sim) const {
  return W_ * Deviation(poses, sim) - offset_;
}

void MotionResidual::Linearize(const std::vector<const double*>& poses, const double* sim, Eigen::VectorXd* dx,
                               std::vector<Eigen::Matrix<double, 6, kVars>>* J) const {
  const int n = num_views();
  dx->resize(6 * n);
  J->resize(n);
  Jet13 pose[6], s[7], d[6];
  for (int i = 0; i < 7; ++i) s[i] = Jet13(sim[i], 6 + i);
  for (int k = 0; k < n; ++k) {
    for (int i = 0; i < 6; ++i) pose[i] = Jet13(poses[k][i], i);
    views_[k](pose, s, d);
    for (int i = 0; i < 6; ++i) {
      (*dx)(6 * k + i) = d[i].a;
      (*J)[k].row(i) = d[i].v.transpose();
    }
  }
}

bool MotionResidual::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const {
  const int n = num_views();
  const double* sim = parameters[n];
  const std::vector<const double*> poses(parameters, parameters + n);
  Eigen::Map<Eigen::VectorXd> r(residuals, 6 * n);
  if (!jacobians) {
    r = Evaluate(poses, sim);
    return true;
  }
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  Eigen::VectorXd dx;
  std::vector<Eigen::Matrix<double, 6, kVars>> J;
  Linearize(poses, sim, &dx, &J);
  Eigen::Matrix<double, Eigen::Dynamic, 7> J_sim = Eigen::Matrix<double, Eigen::Dynamic, 7>::Zero(6 * n, 7);
  for (int k = 0; k < n; ++k) {
    const auto W_k = W_.middleCols<6>(6 * k);  // the columns of W that view k's deviation meets
    if (jacobians[k]) Eigen::Map<RowMajor>(jacobians[k], 6 * n, 6) = W_k * J[k].leftCols<6>();
    J_sim.noalias() += W_k * J[k].rightCols<7>();
  }
  r = W_ * dx - offset_;
  if (jacobians[n]) Eigen::Map<RowMajor>(jacobians[n], 6 * n, 7) = J_sim;
  return true;
}

}  // namespace pgba
