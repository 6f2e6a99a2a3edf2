#include "modules/global_ba/motion_weight.h"

namespace pgba {

MotionWeight MotionWeight::Dense(const Eigen::MatrixXd& W) {
  return MotionWeight(std::make_shared<const Eigen::VectorXd>(Eigen::VectorXd::Ones(W.rows())),
                      std::make_shared<const Eigen::MatrixXd>(W));
}

Eigen::VectorXd MotionWeight::Times(const Eigen::VectorXd& x) const {
  if (!V_) return d_->cwiseProduct(x);
  return d_->cwiseProduct(*V_ * x);
}

Eigen::VectorXd MotionWeight::TransposeTimes(const Eigen::VectorXd& r) const {
  if (!V_) return d_->cwiseProduct(r);
  return V_->transpose() * d_->cwiseProduct(r);
}

Eigen::MatrixXd MotionWeight::ColumnsTimes(int first, const Eigen::MatrixXd& X) const {
  const int n = static_cast<int>(X.rows());
  if (!V_) {
    Eigen::MatrixXd out = Eigen::MatrixXd::Zero(size(), X.cols());
    out.middleRows(first, n) = d_->segment(first, n).asDiagonal() * X;
    return out;
  }
  return d_->asDiagonal() * (V_->middleCols(first, n) * X);
}

Eigen::MatrixXd MotionWeight::Gram() const {
  if (!V_) return d_->cwiseAbs2().asDiagonal();
  return V_->transpose() * d_->cwiseAbs2().asDiagonal() * *V_;
}

}  // namespace pgba
