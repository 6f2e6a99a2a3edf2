// The pose system of the motion-block solver (motion_normal_equations.h): the normal
// equations over the free pose variables (the gauge's left out), one 6 x 6 block per pair of
// poses that share a motion, bordered by the global intrinsic unknowns, factorised densely
// when small and by CHOLMOD when large. Internal to modules/global_ba.
#pragma once

#include <Eigen/Cholesky>
#include <Eigen/CholmodSupport>
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <algorithm>
#include <array>
#include <utility>
#include <vector>

#include "modules/global_ba/motion_normal_equations.h"

namespace pgba {
namespace internal {

// The sparse pose system: free variables (the gauge's are left out), one 6 x 6 block per pair
// of poses that share a motion, lower triangle, with the value index of every block entry;
// then the intrinsic unknowns (after every pose variable), a dense border of a few rows.
class PoseSystem {
 public:
  using Matrix6d = Eigen::Matrix<double, 6, 6>;

  explicit PoseSystem(const MotionBlockProblem& p);

  int num_free() const { return num_free_; }
  int num_pose_vars() const { return num_pose_vars_; }
  int var(int pose, int coord) const { return var_[6 * pose + coord]; }
  // Variable of parameter i of intrinsic block b.
  int intrinsic_var(int block, int i) const { return intrinsic_var_[block] + i; }
  // Block id of the pair (a, b), a >= b.
  int Block(int a, int b) const {
    return static_cast<int>(std::lower_bound(pairs_.begin(), pairs_.end(), std::make_pair(a, b)) - pairs_.begin());
  }
  int num_blocks() const { return static_cast<int>(pairs_.size()); }
  // The system's values are stored once, in the layout of the factorised matrix (the sparse
  // matrix's values, or the dense matrix column by column); a caller keeps sums of blocks in
  // the same layout (a vector of num_values()) and adds blocks to either.
  size_t num_values() const { return value_size_; }
  // values[...] += B, B the block `id` (its lower-triangle entries on the diagonal).
  void AddBlock(int id, const Matrix6d& B, double* values) const {
    const std::array<int, 36>& index = value_index_[id];
    for (int e = 0; e < 36; ++e)
      if (index[e] >= 0) values[index[e]] += B(e / 6, e % 6);
  }
  // The system's values set to `values` (num_values()), the intrinsic border and corner to 0.
  void Load(const std::vector<double>& values);
  // The system's own values (num_values()).
  double* values() { return dense() ? dense_.data() : matrix_.valuePtr(); }
  // Intrinsic variable row, pose variable column (both as returned by var / intrinsic_var).
  double& border(int intrinsic_var, int pose_var) { return border_(intrinsic_var - num_pose_vars_, pose_var); }
  // Lower triangle used (row >= col).
  double& corner(int row_var, int col_var) { return corner_(row_var - num_pose_vars_, col_var - num_pose_vars_); }

  // Factorises the assembled blocks plus `diagonal` (per free variable); false on failure.
  // Small systems are factorised densely (blocked Cholesky: the pose system of a block of a
  // few hundred images is nearly dense, where the simplicial sparse factorisation is ~10x
  // slower), large ones sparsely.
  bool Factorize(const Eigen::VectorXd& diagonal);
  Eigen::VectorXd Solve(const Eigen::VectorXd& b) const {
    if (dense()) return dense_llt_.solve(b);
    return solver_.solve(b);
  }
  bool dense() const { return num_free_ <= kMaxDenseUnknowns; }
  // Pose systems up to this many unknowns are factorised densely (250 images).
  static constexpr int kMaxDenseUnknowns = 1500;

 private:
  int Index(int row, int col) const {
    const int* inner = matrix_.innerIndexPtr();
    const int begin = matrix_.outerIndexPtr()[col], end = matrix_.outerIndexPtr()[col + 1];
    return static_cast<int>(std::lower_bound(inner + begin, inner + end, row) - inner);
  }

  std::vector<int> var_;
  std::vector<int> intrinsic_var_;
  int num_free_ = 0, num_pose_vars_ = 0, num_intrinsic_vars_ = 0;
  std::vector<std::pair<int, int>> pairs_;
  std::vector<std::array<int, 36>> value_index_;  // per block, its entries' places in the values
  size_t value_size_ = 0;
  Eigen::MatrixXd border_, corner_;
  Eigen::SparseMatrix<double> matrix_;
  Eigen::MatrixXd dense_;  // lower triangle used
  Eigen::LLT<Eigen::MatrixXd> dense_llt_;
  // Supernodal (CHOLMOD, as Ceres' SPARSE_SCHUR uses): the pose system of a 2,000-image
  // block (12,000 unknowns, a 6 x 6 block per pair of images sharing a motion of ~15 views)
  // fills in heavily, where Eigen's simplicial LDL^T took ~4 s per factorisation.
  Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower> solver_;
  bool factorised_ = false;  // once: its size in the log
};

}  // namespace internal
}  // namespace pgba
