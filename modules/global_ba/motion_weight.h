// The square-root information W_s of a motion's residual r_s = W_s (x_s - x0_s - n_s), in one
// of three forms: factored as W = diag(d) V (the local Hessian's D_s V_s, paper eq. 5), diagonal
// (V absent: Aver_BA's scalar weights), or only through its Gram matrix h = W^T W (the local
// Hessian itself). Why not the dense product: every global solve builds a residual per motion,
// and forming D V, (6N + K)^2 doubles, for each motion on each solve was 5-8% of the pointless
// BA's time. Why the Gram form: the motion-block solver needs only |W a|^2 = a^T h a and
// W^T W a = h a, and a motion keeps h alone (a second (6N + K)^2 matrix per motion, the factor,
// doubled the memory of the local Hessians).
#pragma once

#include <Eigen/Core>
#include <memory>

#include "modules/local_hessian/symmetric_matrix.h"

namespace pgba {

class MotionWeight {
 public:
  MotionWeight() = default;
  // W = diag(d) V; V null: W = diag(d). The pointers may alias storage that outlives the
  // weight.
  MotionWeight(std::shared_ptr<const Eigen::VectorXd> d, std::shared_ptr<const Eigen::MatrixXd> V)
      : d_(std::move(d)), V_(std::move(V)) {}
  // A dense W (d = 1), owned.
  static MotionWeight Dense(const Eigen::MatrixXd& W);
  // W known through h = W^T W only; `h` is borrowed: it must outlive the weight.
  static MotionWeight OfGram(const SymmetricMatrix& h);

  // Whether W itself is at hand (Times, TransposeTimes, ColumnsTimes), not only h.
  bool factored() const { return static_cast<bool>(d_); }
  int size() const { return h_ ? static_cast<int>(h_->rows()) : static_cast<int>(d_->size()); }
  Eigen::VectorXd Times(const Eigen::VectorXd& x) const;           // W x (factored)
  Eigen::VectorXd TransposeTimes(const Eigen::VectorXd& r) const;  // W^T r (factored)
  // W.middleCols(first, X.rows()) X: the rows of W x that variables first.. meet (factored).
  Eigen::MatrixXd ColumnsTimes(int first, const Eigen::MatrixXd& X) const;
  Eigen::MatrixXd Gram() const;                          // W^T W
  Eigen::VectorXd GramTimes(const Eigen::VectorXd& a) const;  // W^T W a
  double SquaredNorm(const Eigen::VectorXd& a) const;        // |W a|^2

 private:
  std::shared_ptr<const Eigen::VectorXd> d_;
  std::shared_ptr<const Eigen::MatrixXd> V_;
  const SymmetricMatrix* h_ = nullptr;  // the Gram form
};

}  // namespace pgba
