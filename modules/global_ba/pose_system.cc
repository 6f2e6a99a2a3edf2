#include "modules/global_ba/pose_system.h"

#include <algorithm>
#include <utility>

#include "pgba/util/logging.h"
#include "pgba/util/timer.h"

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
  pairs_ = std::move(pairs);
  // Calls f(e, vr, vc) for each entry e = 6 r + c of block k that the system stores: both
  // variables free, in the lower triangle (vr >= vc).
  const auto for_each_stored = [&](size_t k, const auto& f) {
    const auto [a, b] = pairs_[k];
    for (int r = 0; r < 6; ++r)
      for (int c = 0; c < 6; ++c) {
        const int vr = var_[6 * a + r], vc = var_[6 * b + c];
        if (vr >= 0 && vc >= 0 && vr >= vc) f(6 * r + c, vr, vc);
      }
  };
  value_index_.assign(pairs_.size(), {});
  for (std::array<int, 36>& index : value_index_) index.fill(-1);
  if (dense()) {  // the dense matrix, column by column
    dense_.setZero(num_free_, num_free_);
    value_size_ = static_cast<size_t>(num_free_) * num_free_;
    for (size_t k = 0; k < pairs_.size(); ++k)
      for_each_stored(k, [&](int e, int vr, int vc) { value_index_[k][e] = vc * num_free_ + vr; });
    return;
  }
  // The sparse pattern built in place (no list of entries): the entries of each column
  // counted, then written and sorted; the intrinsics' border and corner dense.
  std::vector<int> count(num_free_ + 1, 0);
  for (size_t k = 0; k < pairs_.size(); ++k) for_each_stored(k, [&](int, int, int vc) { ++count[vc + 1]; });
  for (int c = 0; c < num_pose_vars_; ++c) count[c + 1] += num_intrinsic_vars_;  // the border
  for (int c = num_pose_vars_; c < num_free_; ++c) count[c + 1] += num_free_ - c;  // the corner
  for (int c = 0; c < num_free_; ++c) count[c + 1] += count[c];
  matrix_.resize(num_free_, num_free_);
  matrix_.resizeNonZeros(count[num_free_]);
  std::copy(count.begin(), count.end(), matrix_.outerIndexPtr());
  std::vector<int> next(count.begin(), count.end() - 1);
  int* inner = matrix_.innerIndexPtr();
  for (size_t k = 0; k < pairs_.size(); ++k) for_each_stored(k, [&](int, int vr, int vc) { inner[next[vc]++] = vr; });
  for (int c = 0; c < num_free_; ++c) {
    for (int r = std::max(c, num_pose_vars_); r < num_free_; ++r) inner[next[c]++] = r;
    std::sort(inner + count[c], inner + count[c + 1]);
  }
  std::fill(matrix_.valuePtr(), matrix_.valuePtr() + matrix_.nonZeros(), 0.0);
  value_size_ = static_cast<size_t>(matrix_.nonZeros());
  for (size_t k = 0; k < pairs_.size(); ++k)
    for_each_stored(k, [&](int e, int vr, int vc) { value_index_[k][e] = Index(vr, vc); });
  solver_.analyzePattern(matrix_);
  PGBA_LOG_DEBUG << "pose system: " << num_free_ << " unknowns, " << pairs_.size() << " pose-pair blocks, "
                 << matrix_.nonZeros() << " nonzeros; its Cholesky factor " << solver_.cholmod().lnz
                 << " nonzeros; resident " << CurrentRssMb() << " MB";
}

void PoseSystem::Load(const std::vector<double>& values) {
  std::copy(values.begin(), values.end(), this->values());
  border_.setZero();
  corner_.setZero();
}

bool PoseSystem::Factorize(const Eigen::VectorXd& diagonal) {
  const int P = num_pose_vars_;
  if (dense()) {
    dense_.bottomLeftCorner(num_intrinsic_vars_, P) = border_;
    dense_.bottomRightCorner(num_intrinsic_vars_, num_intrinsic_vars_) = corner_;
    dense_.diagonal() += diagonal;
    dense_llt_.compute(dense_);
    return dense_llt_.info() == Eigen::Success;
  }
  double* values = matrix_.valuePtr();
  for (int r = P; r < num_free_; ++r) {
    for (int c = 0; c < P; ++c) values[Index(r, c)] += border_(r - P, c);
    for (int c = P; c <= r; ++c) values[Index(r, c)] += corner_(r - P, c - P);
  }
  for (int i = 0; i < num_free_; ++i) values[Index(i, i)] += diagonal(i);
  solver_.factorize(matrix_);
  if (!factorised_) {
    factorised_ = true;
    PGBA_LOG_DEBUG << "pose system factorised: the factor holds " << solver_.cholmod().memory_inuse / 1048576.0
                   << " MB (" << solver_.cholmod().memory_usage / 1048576.0 << " MB at most while factorising); resident "
                   << CurrentRssMb() << " MB";
  }
  return solver_.info() == Eigen::Success;
}

}  // namespace internal
}  // namespace pgba
