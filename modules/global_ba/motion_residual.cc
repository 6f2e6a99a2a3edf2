#include "modules/global_ba/motion_residual.h"

#include "pgba/geometry/rotation.h"

namespace pgba {

namespace {
constexpr int kVars = 6 + 7;  // one pose block and the similarity
}  // namespace

// With v = C - G, A = r0_k^T R0_k, alpha = alpha0 Exp(theta), D = A Exp(omega) alpha^T and
// phi = Log(D) (right perturbations, Exp(x + d) = Exp(x) Exp(Jr(x) d), R Exp(u) R^T = Exp(R u)):
//   d dc / dC = lambda alpha,  d dc / dbeta = I,  d dc / dlambda = alpha v,
//   d dc / dtheta = -lambda alpha [v]_x Jr(theta)             (alpha Exp(u) v = alpha v - alpha [v]_x u),
//   d phi / domega =  Jr^-1(phi) alpha Jr(omega)              (D' = D Exp(alpha Jr(omega) d)),
//   d phi / dtheta = -Jr^-1(phi) alpha Jr(theta)              (D' = D Exp(-alpha Jr(theta) d)).
void ViewDeviation::Linearize(const double* pose, const double* sim, double* dx,
                              Eigen::Matrix<double, 6, kVars>* J) const {
  (*this)(pose, sim, dx);
  const Eigen::Map<const Eigen::Vector3d> C(pose), omega(pose + 3), theta(sim + 3);
  const double lambda = sim[6];
  const Eigen::Matrix3d alpha = alpha0 * ExpSO3(theta);
  const Eigen::Vector3d v = C - G;
  const Eigen::Matrix3d Jr_theta = RightJacobianSO3(theta);
  const Eigen::Matrix3d Jinv_alpha = InverseRightJacobianSO3(Eigen::Map<const Eigen::Vector3d>(dx + 3)) * alpha;
  J->setZero();
  J->block<3, 3>(0, 0) = lambda * alpha;
  J->block<3, 3>(0, 6).setIdentity();
  J->block<3, 3>(0, 9) = -lambda * alpha * Skew(v) * Jr_theta;
  J->block<3, 1>(0, 12) = alpha * v;
  J->block<3, 3>(3, 3) = Jinv_alpha * RightJacobianSO3(omega);
  J->block<3, 3>(3, 9) = -Jinv_alpha * Jr_theta;
}

MotionResidual::MotionResidual(const std::vector<Eigen::Matrix3d>& R0, const MotionSimilarity& sim,
                               const std::vector<Pose>& x0, MotionWeight W,
                               const Eigen::VectorXd& newton_step, const Eigen::VectorXd& intrinsics0,
                               const std::vector<int>& intrinsic_sizes)
    : W_(std::move(W)), intrinsics0_(intrinsics0), intrinsic_sizes_(intrinsic_sizes) {
  const int n = static_cast<int>(x0.size());
  const int rows = 6 * n + num_intrinsics();
  for (int k = 0; k < n; ++k) views_.push_back({sim.alpha0, sim.G, x0[k].R().transpose() * R0[k], x0[k].C()});
  newton_step_ = newton_step.size() == rows ? newton_step : Eigen::VectorXd::Zero(rows);
  if (W_.factored()) offset_ = W_.Times(newton_step_);
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

double MotionResidual::SquaredNorm(const std::vector<const double*>& poses, const double* sim,
                                   const std::vector<const double*>& intrinsics) const {
  if (W_.factored()) return Evaluate(poses, sim, intrinsics).squaredNorm();
  return W_.SquaredNorm(Deviation(poses, sim, intrinsics) - newton_step_);  // (dx - n)^T h (dx - n)
}

Eigen::VectorXd MotionResidual::DeviationGradient(const Eigen::VectorXd& dx) const {
  if (W_.factored()) return W_.TransposeTimes(W_.Times(dx) - offset_);
  return W_.GramTimes(dx - newton_step_);
}

void MotionResidual::Linearize(const std::vector<const double*>& poses, const double* sim,
                               const std::vector<const double*>& intrinsics, Eigen::VectorXd* dx,
                               std::vector<Eigen::Matrix<double, 6, kVars>>* J) const {
  const int n = num_views();
  dx->resize(6 * n + num_intrinsics());
  IntrinsicDeviation(intrinsics, dx->data() + 6 * n);
  J->resize(n);
  for (int k = 0; k < n; ++k) views_[k].Linearize(poses[k], sim, dx->data() + 6 * k, &(*J)[k]);
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
