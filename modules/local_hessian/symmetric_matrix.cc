#include "modules/local_hessian/symmetric_matrix.h"

#include <algorithm>
#include <limits>

namespace pgba {

SymmetricMatrix::SymmetricMatrix(const Eigen::MatrixXd& dense) : n_(static_cast<int>(dense.rows())) {
  data_.resize(static_cast<Eigen::Index>(n_) * (n_ + 1) / 2);
  for (int c = 0; c < n_; ++c) data_.segment(Index(c, c), n_ - c) = dense.col(c).tail(n_ - c);
}

Eigen::MatrixXd SymmetricMatrix::Dense() const {
  Eigen::MatrixXd out(n_, n_);
  for (int c = 0; c < n_; ++c) {
    out.col(c).tail(n_ - c) = data_.segment(Index(c, c), n_ - c);
    out.row(c).tail(n_ - c) = data_.segment(Index(c, c), n_ - c).transpose();
  }
  return out;
}

Eigen::VectorXd SymmetricMatrix::operator*(const Eigen::VectorXd& x) const {
  Eigen::VectorXd y = Eigen::VectorXd::Zero(n_);
  for (int c = 0; c < n_; ++c) {
    const auto column = data_.segment(Index(c, c), n_ - c);  // rows c..n-1 of column c
    y.tail(n_ - c) += column * x(c);
    y(c) += column.tail(n_ - c - 1).dot(x.tail(n_ - c - 1));
  }
  return y;
}

double SymmetricMatrix::MaxDiagonal() const {
  double m = -std::numeric_limits<double>::infinity();
  for (int c = 0; c < n_; ++c) m = std::max(m, data_(Index(c, c)));
  return m;
}

}  // namespace pgba
