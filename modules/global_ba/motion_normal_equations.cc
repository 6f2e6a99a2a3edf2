#include "modules/global_ba/motion_normal_equations.h"

#include "modules/global_ba/motion_term_system.h"
#include "modules/global_ba/pose_system.h"
#include "pgba/util/timer.h"

#include <tbb/parallel_for.h>

#include <Eigen/Cholesky>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace pgba {

using internal::IntrinsicPointers;
using internal::Linearize;
using internal::Matrix6d;
using internal::Matrix7d;
using internal::OptimizeSimilarity;
using internal::PosePointers;
using internal::TermSystem;
using internal::Vector6d;
using internal::Vector7d;

namespace {

// Ceres' bounds on the Levenberg-Marquardt diagonal.
constexpr double kMinDiagonal = 1e-6;
constexpr double kMaxDiagonal = 1e32;
// Ceres' min_relative_decrease: a step is taken when the cost falls by this share of the
// model's prediction.
constexpr double kMinRelativeDecrease = 1e-3;

Vector7d Clamped(const Vector7d& d) { return d.cwiseMax(kMinDiagonal).cwiseMin(kMaxDiagonal); }


}  // namespace

double MotionBlockCost(const MotionBlockProblem& p) {
  // Terms evaluated in parallel, summed in term order: the same bits for any thread count.
  std::vector<double> costs(p.terms.size());
  tbb::parallel_for(size_t(0), p.terms.size(), [&](size_t ti) {
    const MotionBlockTerm& t = p.terms[ti];
    costs[ti] = 0.5 * t.weight * t.residual->SquaredNorm(PosePointers(p, t), t.sim, IntrinsicPointers(p, t));
  });
  double cost = 0.0;
  for (const double c : costs) cost += c;
  return cost;
}

namespace {

// The per-term maps from local rows to system variables.
struct TermIndex {
  std::vector<int> block_of;  // k * N + l -> pose pair block id
  std::vector<int> kvar;      // intrinsic row of h -> variable
};

// Assembles the reduced system of the current linearisation with each motion's similarity
// eliminated (its 7 x 7 block damped by diag / radius; radius = inf: undamped): the system's
// blocks (`pose_blocks`, the sum of the motions' H_kl, minus each motion's
// H_k,sim H_sim^-1 H_sim,l), the right-hand side -g + H_x,sim H_sim^-1 g_sim, and each term's
// H_sim^-1.
void AssembleReduced(const MotionBlockProblem& p, const std::vector<TermSystem>& sys,
                     const std::vector<TermIndex>& index, const std::vector<double>& pose_blocks,
                     const Eigen::VectorXd& gradient, double radius, internal::PoseSystem* system,
                     Eigen::VectorXd* rhs, std::vector<Matrix7d>* Hss_inv) {
  system->Load(pose_blocks);
  double* values = system->values();
  *rhs = -gradient;
  Hss_inv->resize(p.terms.size());
  for (size_t ti = 0; ti < p.terms.size(); ++ti) {
    const TermSystem& s = sys[ti];
    const MotionBlockTerm& t = p.terms[ti];
    const TermIndex& ix = index[ti];
    const int n = static_cast<int>(t.poses.size());
    const int K = static_cast<int>(ix.kvar.size());
    Matrix7d Hss = s.Hss;
    if (std::isfinite(radius)) Hss.diagonal() += Clamped(s.Hss.diagonal()) / radius;
    (*Hss_inv)[ti] = Hss.ldlt().solve(Matrix7d::Identity());
    const Eigen::Matrix<double, Eigen::Dynamic, 7> M = s.Hps * (*Hss_inv)[ti];  // 6N x 7
    const Eigen::VectorXd Mg = M * s.gs;
    for (int k = 0; k < n; ++k) {
      for (int l = 0; l < n; ++l) {
        if (t.poses[k] < t.poses[l]) continue;  // lower triangle by pose index
        const Matrix6d correction = -M.middleRows<6>(6 * k) * s.Hps.middleRows<6>(6 * l).transpose();
        system->AddBlock(ix.block_of[k * n + l], correction, values);
      }
      for (int c = 0; c < 6; ++c) {
        const int v = system->var(t.poses[k], c);
        if (v >= 0) (*rhs)(v) += Mg(6 * k + c);
      }
    }
    if (K == 0) continue;
    // Intrinsic rows: H_kx - H_k,sim H_sim^-1 H_sim,x for x = poses and intrinsics.
    const Eigen::Matrix<double, Eigen::Dynamic, 7> N = s.Hsk.transpose() * (*Hss_inv)[ti];  // K x 7
    const Eigen::MatrixXd pose_border = s.Hpk.transpose() - N * s.Hps.transpose();          // K x 6N
    const Eigen::MatrixXd corner = s.Hkk - N * s.Hsk;
    const Eigen::VectorXd Ng = N * s.gs;
    for (int i = 0; i < K; ++i) {
      for (int k = 0; k < n; ++k)
        for (int c = 0; c < 6; ++c)
          if (const int v = system->var(t.poses[k], c); v >= 0) system->border(ix.kvar[i], v) += pose_border(i, 6 * k + c);
      for (int j = 0; j < K; ++j)
        if (ix.kvar[i] >= ix.kvar[j]) system->corner(ix.kvar[i], ix.kvar[j]) += corner(i, j);
      (*rhs)(ix.kvar[i]) += Ng(i);
    }
  }
}

}  // namespace

MotionBlockSummary SolveMotionBlocks(const MotionBlockProblem& p, const MotionBlockSolverOptions& options,
                                     const MotionBlockCallback& callback) {
  MotionBlockSummary summary;
  internal::PoseSystem system(p);
  std::vector<const SymmetricMatrix*> h(p.terms.size());
  std::vector<TermIndex> index(p.terms.size());
  // Freed memory is handed back to the system only when there is much of it: the motions'
  // pose-pair blocks hold as many doubles as their h, and on a small problem returning them
  // only makes the next linearisation fault the same pages in again.
  constexpr double kReleaseAboveBytes = 64.0 * (1 << 20);
  double hessian_bytes = 0.0;
  for (const MotionBlockTerm& t : p.terms)
    hessian_bytes += 4.0 * static_cast<double>(t.h->rows()) * static_cast<double>(t.h->rows() + 1);
  const auto release = [&] {
    if (hessian_bytes > kReleaseAboveBytes) ReleaseFreeMemory();
  };
  for (size_t ti = 0; ti < p.terms.size(); ++ti) {
    const MotionBlockTerm& t = p.terms[ti];
    h[ti] = t.h;
    const int n = static_cast<int>(t.poses.size());
    index[ti].block_of.resize(n * n);
    for (int k = 0; k < n; ++k)
      for (int l = 0; l < n; ++l)
        index[ti].block_of[k * n + l] =
            system.Block(std::max(t.poses[k], t.poses[l]), std::min(t.poses[k], t.poses[l]));
    for (const int b : t.intrinsics)
      for (int i = 0; i < p.intrinsics[b]->size(); ++i) index[ti].kvar.push_back(system.intrinsic_var(b, i));
  }

  release();  // the pattern's construction: before the factor takes its place
  double cost = MotionBlockCost(p);
  summary.initial_cost = summary.final_cost = cost;
  if (!std::isfinite(cost)) {
    summary.usable = false;
    summary.message = "non-finite initial cost";
    return summary;
  }
  if (callback) callback(0, cost);
  double radius = options.initial_trust_region_radius, nu = 2.0;
  int accepted = 0;  // steps taken
  const int m = static_cast<int>(p.poses.size());
  const int num_intrinsic_blocks = static_cast<int>(p.intrinsics.size());
  std::vector<TermSystem> sys(p.terms.size());
  bool relinearize = true;
  Eigen::VectorXd gradient(system.num_free()), diagonal(system.num_free());
  // The sum over the motions of their pose-pair blocks H_kl, one per block of the pose system.
  // (In the system's value layout: PoseSystem::AddBlock.)
  std::vector<double> pose_blocks(system.num_values());
  // Linearises every term at the current state: the gradient, diag(J^T J) per variable and the
  // pose blocks. A term's H_kl (N^2 blocks, as many doubles as its h) are summed into the pose
  // blocks and released chunk by chunk: together they would hold a second copy of every h.
  const auto linearize_all = [&]() {
    gradient.setZero();
    diagonal.setZero();
    std::fill(pose_blocks.begin(), pose_blocks.end(), 0.0);
    constexpr size_t kChunk = 256;
    for (size_t begin = 0; begin < p.terms.size(); begin += kChunk) {
      const size_t end = std::min(p.terms.size(), begin + kChunk);
      // Each term writes only its own system (half of a solve's time on one thread); the sums
      // below run in term order, so the result does not depend on the schedule.
      tbb::parallel_for(begin, end, [&](size_t ti) { sys[ti] = Linearize(p, p.terms[ti], h[ti]->Dense()); });
      for (size_t ti = begin; ti < end; ++ti) {
        const MotionBlockTerm& t = p.terms[ti];
        const size_t n = t.poses.size();
        for (size_t k = 0; k < n; ++k) {
          for (int c = 0; c < 6; ++c) {
            const int v = system.var(t.poses[k], c);
            if (v < 0) continue;
            gradient(v) += sys[ti].gp(6 * k + c);
            diagonal(v) += sys[ti].Hpp[k * n + k](c, c);
          }
          for (size_t l = 0; l < n; ++l)  // lower triangle by pose index
            if (t.poses[k] >= t.poses[l])
              system.AddBlock(index[ti].block_of[k * n + l], sys[ti].Hpp[k * n + l], pose_blocks.data());
        }
        std::vector<Matrix6d>().swap(sys[ti].Hpp);
        for (size_t i = 0; i < index[ti].kvar.size(); ++i) {
          gradient(index[ti].kvar[i]) += sys[ti].gk(i);
          diagonal(index[ti].kvar[i]) += sys[ti].Hkk(i, i);
        }
      }
    }
  };
  std::vector<Matrix7d> Hss_inv;
  Eigen::VectorXd rhs;
  for (int iteration = 1; iteration <= options.max_iterations; ++iteration) {
    if (relinearize) {
      linearize_all();
      relinearize = false;
      release();  // the motions' pose-pair blocks, summed and freed chunk by chunk
    }
    // Damped reduced system: each motion's similarity eliminated with its damped 7 x 7 block.
    AssembleReduced(p, sys, index, pose_blocks, gradient, radius, &system, &rhs, &Hss_inv);
    Eigen::VectorXd damping(system.num_free());
    for (int i = 0; i < system.num_free(); ++i)
      damping(i) = std::min(std::max(diagonal(i), kMinDiagonal), kMaxDiagonal) / radius;
    if (!system.Factorize(damping)) {
      summary.usable = false;
      summary.message = "the reduced pose system could not be factorised";
      return summary;
    }
    const Eigen::VectorXd dp = system.Solve(rhs);
    if (!dp.allFinite()) {
      summary.usable = false;
      summary.message = "non-finite step";
      return summary;
    }
    // Back-substitution of the similarities and the model's predicted decrease.
    std::vector<Vector6d> pose_step(m, Vector6d::Zero());
    for (int i = 0; i < m; ++i)
      for (int c = 0; c < 6; ++c)
        if (const int v = system.var(i, c); v >= 0) pose_step[i](c) = dp(v);
    std::vector<Eigen::VectorXd> intrinsic_step(num_intrinsic_blocks);
    for (int b = 0; b < num_intrinsic_blocks; ++b) {
      intrinsic_step[b].resize(p.intrinsics[b]->size());
      for (int i = 0; i < intrinsic_step[b].size(); ++i) intrinsic_step[b](i) = dp(system.intrinsic_var(b, i));
    }
    std::vector<Vector7d> sim_step(p.terms.size());
    double predicted = 0.0, step_norm2 = 0.0, x_norm2 = 0.0;
    for (size_t ti = 0; ti < p.terms.size(); ++ti) {
      const TermSystem& s = sys[ti];
      const MotionBlockTerm& t = p.terms[ti];
      const int n = static_cast<int>(t.poses.size());
      const int K = static_cast<int>(index[ti].kvar.size());
      Eigen::VectorXd dk(K);
      for (int i = 0; i < K; ++i) dk(i) = dp(index[ti].kvar[i]);
      Vector7d b = s.gs;
      for (int k = 0; k < n; ++k) b += s.Hps.middleRows<6>(6 * k).transpose() * pose_step[t.poses[k]];
      if (K > 0) b += s.Hsk * dk;
      sim_step[ti] = -Hss_inv[ti] * b;
      Eigen::VectorXd jd(6 * n + K);
      for (int k = 0; k < n; ++k) jd.segment<6>(6 * k) = s.A[k] * pose_step[t.poses[k]] + s.B[k] * sim_step[ti];
      jd.tail(K) = dk;
      const double quad = t.weight * jd.dot(*h[ti] * jd);
      double lin = s.gs.dot(sim_step[ti]) + s.gk.dot(dk);
      for (int k = 0; k < n; ++k) lin += s.gp.segment<6>(6 * k).dot(pose_step[t.poses[k]]);
      predicted += -lin - 0.5 * quad;
      step_norm2 += sim_step[ti].squaredNorm();
      x_norm2 += Eigen::Map<const Vector7d>(t.sim).squaredNorm();
    }
    for (int i = 0; i < m; ++i) {
      step_norm2 += pose_step[i].squaredNorm();
      x_norm2 += p.poses[i]->x.squaredNorm();
    }
    for (int b = 0; b < num_intrinsic_blocks; ++b) {
      step_norm2 += intrinsic_step[b].squaredNorm();
      x_norm2 += p.intrinsics[b]->squaredNorm();
    }
    // Trial step.
    std::vector<PoseVector> saved_poses(m);
    std::vector<Vector7d> saved_sims(p.terms.size());
    std::vector<Eigen::VectorXd> saved_intrinsics(num_intrinsic_blocks);
    for (int i = 0; i < m; ++i) {
      saved_poses[i] = p.poses[i]->x;
      p.poses[i]->x += pose_step[i];
    }
    for (size_t ti = 0; ti < p.terms.size(); ++ti) {
      Eigen::Map<Vector7d> x(p.terms[ti].sim);
      saved_sims[ti] = x;
      x += sim_step[ti];
    }
    for (int b = 0; b < num_intrinsic_blocks; ++b) {
      saved_intrinsics[b] = *p.intrinsics[b];
      *p.intrinsics[b] += intrinsic_step[b];
    }
    if (options.embedded_similarity_iterations > 0)
      tbb::parallel_for(size_t(0), p.terms.size(), [&](size_t ti) {
        OptimizeSimilarity(p, p.terms[ti], h[ti]->Dense(), options.embedded_similarity_iterations);
      });
    const double new_cost = MotionBlockCost(p);
    const double rho = predicted > 0 ? (cost - new_cost) / predicted : -1.0;
    summary.iterations = iteration;
    if (std::isfinite(new_cost) && rho > kMinRelativeDecrease) {
      ++accepted;
      const double decrease = cost - new_cost;
      cost = new_cost;
      radius = radius / std::max(1.0 / 3.0, 1.0 - std::pow(2.0 * rho - 1.0, 3));
      nu = 2.0;
      relinearize = true;
      if (callback) callback(iteration, cost);
      if (decrease <= options.function_tolerance * (cost + decrease)) break;
      if (std::sqrt(step_norm2) <= options.parameter_tolerance * (std::sqrt(x_norm2) + options.parameter_tolerance))
        break;
    } else {
      for (int i = 0; i < m; ++i) p.poses[i]->x = saved_poses[i];
      for (size_t ti = 0; ti < p.terms.size(); ++ti) Eigen::Map<Vector7d>(p.terms[ti].sim) = saved_sims[ti];
      for (int b = 0; b < num_intrinsic_blocks; ++b) *p.intrinsics[b] = saved_intrinsics[b];
      radius /= nu;
      nu *= 2.0;
      if (callback) callback(iteration, cost);
      if (options.stop_at_refused_step && accepted > 0) break;
      if (std::sqrt(step_norm2) <= options.parameter_tolerance * (std::sqrt(x_norm2) + options.parameter_tolerance))
        break;
    }
  }
  summary.final_cost = cost;
  summary.final_radius = radius;
  const int P = system.num_pose_vars(), K = system.num_free() - P;
  if (K > 0) {
    // (J^T J)^-1 on the intrinsics at the solution: the intrinsic block of the inverse of the
    // undamped reduced system (the inverse of a Schur complement is the block of the inverse).
    linearize_all();
    AssembleReduced(p, sys, index, pose_blocks, gradient, std::numeric_limits<double>::infinity(), &system, &rhs,
                    &Hss_inv);
    if (system.Factorize(Eigen::VectorXd::Zero(system.num_free()))) {
      summary.intrinsics_inverse_hessian.resize(K, K);
      for (int j = 0; j < K; ++j) {
        Eigen::VectorXd e = Eigen::VectorXd::Zero(system.num_free());
        e(P + j) = 1.0;
        summary.intrinsics_inverse_hessian.col(j) = system.Solve(e).tail(K);
      }
    }
  }
  return summary;
}

}  // namespace pgba
