// A symmetric matrix stored once: its lower triangle, column by column, n (n + 1) / 2 doubles
// instead of n^2. A motion's local Hessian h is (6N + K) square and symmetric, and the largest
// memory of a large block is one h per motion: the other triangle is not stored.
#pragma once

#include <Eigen/Core>
#include <cstddef>

namespace pgba {

class SymmetricMatrix {
 public:
  SymmetricMatrix() = default;
  // The lower triangle of `dense` (its upper one is not read, as Eigen's LDLT and
  // SelfAdjointEigenSolver do not read it either).
  explicit SymmetricMatrix(const Eigen::MatrixXd& dense);

  int rows() const { return n_; }
  int cols() const { return n_; }
  bool empty() const { return n_ == 0; }
  // Entry (r, c), either triangle.
  double operator()(int r, int c) const { return r >= c ? data_(Index(r, c)) : data_(Index(c, r)); }
  // The full matrix, both triangles.
  Eigen::MatrixXd Dense() const;
  Eigen::VectorXd operator*(const Eigen::VectorXd& x) const;
  bool allFinite() const { return data_.allFinite(); }
  double MaxDiagonal() const;
  bool operator==(const SymmetricMatrix& o) const { return n_ == o.n_ && data_ == o.data_; }

 private:
  // Column c of the lower triangle starts after the c columns before it.
  size_t Index(int r, int c) const {
    return static_cast<size_t>(c) * n_ - static_cast<size_t>(c) * (c - 1) / 2 + (r - c);
  }
  int n_ = 0;
  Eigen::VectorXd data_;
};

}  // namespace pgba
