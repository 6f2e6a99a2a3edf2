#include "modules/global_ba/motion_residual.h"

#include <ceres/jet.h>

namespace pgba {

namespace {
constexpr int kVars = 6 + 7;  // one pose block and the similarity
using Jet13 = ceres::Jet<double, kVars>;
}  // namespace

MotionResidual::MotionResidual(const std::vector<Eigen::Matrix3d>& R0, const MotionSimilarity& sim,
                               const std::vector<Pose>& x0, MotionWeight W,
                               const Eigen::VectorXd& newton_step, const Eigen::VectorXd& intrinsics0,
                               const std::vector<int>& intrinsic_sizes)
    : W_(std::move(W)), intrinsics0_(intrinsics0), intrinsic_sizes_(intrinsic_sizes) {
  const int n = static_cast<int>(x0.size());
  const int rows = 6 * n + num_intrinsics();
  for (int k = 0; k < n; ++k) views_.push_back({sim.alpha0, sim.G, x0[k].R().transpose() * R0[k], x0[k].C()});
  offset_ = newton_step.size() == rows ? W_.Times(newton_step) : Eigen::VectorXd::Zero(rows);
  set_num_residuals(rows);
  for (int k = 0; k < n; ++k) mutable_parameter_block_sizes()->push_back(6);
  mutable_parameter_block_sizes()->push_back(7);
  for (const int size : intrinsic_sizes_) mutable_parameter_block_sizes()->push_back(size);
}

void MotionResidual::IntrinsicDeviation(const std::vector<const double*>& intrinsics, double* out) const {
  for (size_t c = 0, row = 0; c < intrinsic_sizes_.size(); row += intrinsic_sizes_[c], ++c)
    for (int i = 0; i < intrinsic_sizes_[c]; ++i) out[row + i] = intrinsics[c][i] - intrinsics0_(row + i);
}

Eigen::VectorXd MotionResidual::Deviation(const std::vector<const double*>& poses, const double* sim,
                                          const std::vector<const double*>& intrinsics) const {
  Eigen::VectorXd dx(6 * num_views() + num_intrinsics());
  for (int k = 0; k < num_views(); ++k) views_[k](poses[k], sim, dx.data() + 6 * k);
  IntrinsicDeviation(intrinsics, dx.data() + 6 * num_views());
  return dx;
}

Eigen::VectorXd MotionResidual::Evaluate(const std::vector<const double*>& poses, const double* sim,
                                         const std::vector<const double*>& intrinsics) const {
  return W_.Times(Deviation(poses, sim, intrinsics)) - offset_;
}

void MotionResidual::Linearize(const std::vector<const double*>& poses, const double* sim,
                               const std::vector<const double*>& intrinsics, Eigen::VectorXd* dx,
                               std::vector<Eigen::Matrix<double, 6, kVars>>* J) const {
  const int n = num_views();
  dx->resize(6 * n + num_intrinsics());
  IntrinsicDeviation(intrinsics, dx->data() + 6 * n);
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
  const int rows = 6 * n + num_intrinsics();
  const double* sim = parameters[n];
  const std::vector<const double*> poses(parameters, parameters + n);
  const std::vector<const double*> intrinsics(parameters + n + 1, parameters + n + 1 + intrinsic_sizes_.size());
  Eigen::Map<Eigen::VectorXd> r(residuals, rows);
  if (!jacobians) {
    r = Evaluate(poses, sim, intrinsics);
    return true;
  }
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  Eigen::VectorXd dx;
  std::vector<Eigen::Matrix<double, 6, kVars>> J;
  Linearize(poses, sim, intrinsics, &dx, &J);
  Eigen::Matrix<double, Eigen::Dynamic, 7> J_sim = Eigen::Matrix<double, Eigen::Dynamic, 7>::Zero(rows, 7);
  for (int k = 0; k < n; ++k) {  // the columns of W that view k's deviation meets
    if (jacobians[k]) Eigen::Map<RowMajor>(jacobians[k], rows, 6) = W_.ColumnsTimes(6 * k, J[k].leftCols<6>());
    J_sim.noalias() += W_.ColumnsTimes(6 * k, J[k].rightCols<7>());
  }
  r = W_.Times(dx) - offset_;
  if (jacobians[n]) Eigen::Map<RowMajor>(jacobians[n], rows, 7) = J_sim;
  for (size_t c = 0, col = 6 * n; c < intrinsic_sizes_.size(); col += intrinsic_sizes_[c], ++c)
    if (jacobians[n + 1 + c])  // d dx / d kappa_c = I: the columns of W that kappa_c meets
      Eigen::Map<RowMajor>(jacobians[n + 1 + c], rows, intrinsic_sizes_[c]) =
          W_.ColumnsTimes(static_cast<int>(col), Eigen::MatrixXd::Identity(intrinsic_sizes_[c], intrinsic_sizes_[c]));
  return true;
}

}  // namespace pgba
