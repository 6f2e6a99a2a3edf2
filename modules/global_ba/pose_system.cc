#include "modules/global_ba/pose_system.h"

#include <algorithm>

namespace pgba {
namespace internal {

PoseSystem::PoseSystem(const MotionBlockProblem& p) {
  const int m = static_cast<int>(p.poses.size());
  var_.assign(6 * m, -1);
  int n = 0;
  for (int i = 0; i < m; ++i)
    for (int c = 0; c < 6; ++c) {
      const bool fixed = i == p.fixed_pose || (i == p.scale_pose && c == p.scale_coord);
      if (!fixed) var_[6 * i + c] = n++;
    }
  num_pose_vars_ = n;
  for (const Eigen::VectorXd* k : p.intrinsics) {
    intrinsic_var_.push_back(n);
    n += static_cast<int>(k->size());
  }
  num_free_ = n;
  num_intrinsic_vars_ = num_free_ - num_pose_vars_;
  border_.setZero(num_intrinsic_vars_, num_pose_vars_);
  corner_.setZero(num_intrinsic_vars_, num_intrinsic_vars_);
  std::vector<std::pair<int, int>> pairs;
  for (int i = 0; i < m; ++i) pairs.emplace_back(i, i);
  for (const MotionBlockTerm& t : p.terms)
    for (const int a : t.poses)
      for (const int b : t.poses)
        if (a > b) pairs.emplace_back(a, b);
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  pairs_ = pairs;
  blocks_.assign(pairs_.size(), Matrix6d::Zero());
  if (dense()) return;  // the sparse structure serves only the sparse factorisation
  std::vector<Eigen::Triplet<double>> entries;
  for (const auto& [a, b] : pairs_)
    for (int r = 0; r < 6; ++r)
      for (int c = 0; c < 6; ++c) {
        const int vr = var_[6 * a + r], vc = var_[6 * b + c];
        if (vr >= 0 && vc >= 0 && vr >= vc) entries.emplace_back(vr, vc, 1.0);
      }
  for (int r = num_pose_vars_; r < num_free_; ++r)
    for (int c = 0; c <= r; ++c) entries.emplace_back(r, c, 1.0);  // border and corner: dense
  matrix_.resize(num_free_, num_free_);
  matrix_.setFromTriplets(entries.begin(), entries.end());
  matrix_.makeCompressed();
  value_index_.resize(pairs_.size());
  for (size_t k = 0; k < pairs_.size(); ++k) {
    const auto [a, b] = pairs_[k];
    for (int r = 0; r < 6; ++r)
      for (int c = 0; c < 6; ++c) {
        const int vr = var_[6 * a + r], vc = var_[6 * b + c];
        value_index_[k][6 * r + c] = vr >= 0 && vc >= 0 && vr >= vc ? Index(vr, vc) : -1;
      }
  }
  solver_.analyzePattern(matrix_);
}

bool PoseSystem::Factorize(const Eigen::VectorXd& diagonal) {
  const int P = num_pose_vars_;
  if (dense()) {
    dense_.setZero(num_free_, num_free_);
    for (size_t k = 0; k < pairs_.size(); ++k) {
      const auto [a, b] = pairs_[k];
      for (int r = 0; r < 6; ++r)
        for (int c = 0; c < 6; ++c) {
          const int vr = var_[6 * a + r], vc = var_[6 * b + c];
          if (vr >= 0 && vc >= 0 && vr >= vc) dense_(vr, vc) += blocks_[k](r, c);
        }
    }
    dense_.bottomLeftCorner(num_intrinsic_vars_, P) = border_;
    dense_.bottomRightCorner(num_intrinsic_vars_, num_intrinsic_vars_) = corner_;
    dense_.diagonal() += diagonal;
    dense_llt_.compute(dense_);
    return dense_llt_.info() == Eigen::Success;
  }
  double* values = matrix_.valuePtr();
  std::fill(values, values + matrix_.nonZeros(), 0.0);
  for (size_t k = 0; k < pairs_.size(); ++k)
    for (int e = 0; e < 36; ++e)
      if (value_index_[k][e] >= 0) values[value_index_[k][e]] += blocks_[k](e / 6, e % 6);
  for (int r = P; r < num_free_; ++r) {
    for (int c = 0; c < P; ++c) values[Index(r, c)] += border_(r - P, c);
    for (int c = P; c <= r; ++c) values[Index(r, c)] += corner_(r - P, c - P);
  }
  for (int i = 0; i < num_free_; ++i) matrix_.coeffRef(i, i) += diagonal(i);
  solver_.factorize(matrix_);
  return solver_.info() == Eigen::Success;
}

}  // namespace internal
}  // namespace pgba
