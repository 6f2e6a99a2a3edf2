// The square-root information W_s of a motion's residual r_s = W_s (x_s - x0_s - n_s), kept
// factored as W = diag(d) V (the local Hessian's D_s and V_s, paper eq. 5; V absent: a
// diagonal W, Aver_BA's scalar weights). Why not the dense product: every global solve
// builds a residual per motion, and forming D V, (6N + K)^2 doubles, for each motion on each
// solve was 5-8% of the pointless BA's time; the block solver needs only W x and W^T r.
#pragma once

#include <Eigen/Core>
#include <memory>

namespace pgba {

class MotionWeight {
 public:
  MotionWeight() = default;
  // W = diag(d) V; V null: W = diag(d). The pointers may alias storage that outlives the
  // weight (a LocalHessian's D and V).
  MotionWeight(std::shared_ptr<const Eigen::VectorXd> d, std::shared_ptr<const Eigen::MatrixXd> V)
      : d_(std::move(d)), V_(std::move(V)) {}
  // A dense W (d = 1), owned.
  static MotionWeight Dense(const Eigen::MatrixXd& W);

  int size() const { return static_cast<int>(d_->size()); }
  Eigen::VectorXd Times(const Eigen::VectorXd& x) const;           // W x
  Eigen::VectorXd TransposeTimes(const Eigen::VectorXd& r) const;  // W^T r
  // W.middleCols(first, X.rows()) X: the rows of W x that variables first.. meet.
  Eigen::MatrixXd ColumnsTimes(int first, const Eigen::MatrixXd& X) const;
  Eigen::MatrixXd Gram() const;  // W^T W

 private:
  std::shared_ptr<const Eigen::VectorXd> d_;
  std::shared_ptr<const Eigen::MatrixXd> V_;
};

}  // namespace pgba
