#include "modules/global_ba/motion_weight.h"

#include <stdexcept>

namespace pgba {

MotionWeight MotionWeight::Dense(const Eigen::MatrixXd& W) {
  return MotionWeight(std::make_shared<const Eigen::VectorXd>(Eigen::VectorXd::Ones(W.rows())),
                      std::make_shared<const Eigen::MatrixXd>(W));
}

MotionWeight MotionWeight::OfGram(const SymmetricMatrix& h) {
  MotionWeight w;
  w.h_ = &h;
  return w;
}

namespace {

void RequireFactored(bool factored) {
  if (!factored) throw std::logic_error("MotionWeight: W itself is needed, but only W^T W is held");
}

}  // namespace

Eigen::VectorXd MotionWeight::Times(const Eigen::VectorXd& x) const {
  RequireFactored(factored());
  if (!V_) return d_->cwiseProduct(x);
  return d_->cwiseProduct(*V_ * x);
}

Eigen::VectorXd MotionWeight::TransposeTimes(const Eigen::VectorXd& r) const {
  RequireFactored(factored());
  if (!V_) return d_->cwiseProduct(r);
  return V_->transpose() * d_->cwiseProduct(r);
}

Eigen::MatrixXd MotionWeight::ColumnsTimes(int first, const Eigen::MatrixXd& X) const {
  RequireFactored(factored());
  const int n = static_cast<int>(X.rows());
  if (!V_) {
    Eigen::MatrixXd out = Eigen::MatrixXd::Zero(size(), X.cols());
    out.middleRows(first, n) = d_->segment(first, n).asDiagonal() * X;
    return out;
  }
  return d_->asDiagonal() * (V_->middleCols(first, n) * X);
}

Eigen::MatrixXd MotionWeight::Gram() const {
  if (h_) return h_->Dense();
  if (!V_) return d_->cwiseAbs2().asDiagonal();
  return V_->transpose() * d_->cwiseAbs2().asDiagonal() * *V_;
}

Eigen::VectorXd MotionWeight::GramTimes(const Eigen::VectorXd& a) const {
  if (h_) return *h_ * a;
  return TransposeTimes(Times(a));
}

double MotionWeight::SquaredNorm(const Eigen::VectorXd& a) const {
  if (h_) return a.dot(*h_ * a);
  return Times(a).squaredNorm();
}

}  // namespace pgba
