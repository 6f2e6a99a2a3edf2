#include "averaging/translation_refinement.h"

#include <ceres/ceres.h>

#include "pgba/optim/ceres_solver_options.h"

#include <algorithm>

namespace pgba {
namespace {

// r = obs - sigma (C_b - C_a): BATA's residual (Zhuang et al. 2018). The observation has
// the magnitude of a baseline in its own normalisation (|u| = 1 for pairs, |v| <= 1 for
// triplets), so r is a relative error and cannot be reduced by shrinking the solution.
struct ScaledBaselineError {
  explicit ScaledBaselineError(const Eigen::Vector3d& obs) : obs_(obs) {}
  template <typename T>
  bool operator()(const T* C_a, const T* C_b, const T* sigma, T* r) const {
    for (int k = 0; k < 3; ++k) r[k] = T(obs_(k)) - sigma[0] * (C_b[k] - C_a[k]);
    return true;
  }
  static ceres::CostFunction* Create(const Eigen::Vector3d& obs) {
    return new ceres::AutoDiffCostFunction<ScaledBaselineError, 3, 3, 3, 1>(new ScaledBaselineError(obs));
  }
  Eigen::Vector3d obs_;
};

}  // namespace

int RefineCentres(const std::vector<TripletBaseline>& baselines, const std::vector<PairDirection>& pairs,
                  const TranslationAveragingOptions& options, int fixed_node, int fixed_triplet,
                  Eigen::MatrixXd* centres, std::vector<double>* sizes) {
  // Row-major copy: one contiguous parameter block per centre.
  const int n = static_cast<int>(centres->rows());
  std::vector<Eigen::Vector3d> C(n);
  for (int i = 0; i < n; ++i) C[i] = centres->row(i).transpose();
  // The inverse scales of the triplets then of the pairs, in one buffer: Ceres orders the
  // blocks of an elimination group by address, so two separate allocations would make the
  // elimination order (and the result's last bits) depend on where the heap put them.
  std::vector<double> inverse_scales(sizes->size() + pairs.size(), 0.0);
  double* sigma = inverse_scales.data();
  double* pair_sigma = inverse_scales.data() + sizes->size();
  for (size_t t = 0; t < sizes->size(); ++t) sigma[t] = 1.0 / (*sizes)[t];

  ceres::Problem::Options problem_options;
  problem_options.loss_function_ownership = ceres::TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  auto loss = [&](double weight) {
    return new ceres::ScaledLoss(options.refine_loss.CreateLossFunction(), weight, ceres::TAKE_OWNERSHIP);
  };
  for (const TripletBaseline& b : baselines)
    problem.AddResidualBlock(ScaledBaselineError::Create(b.v), loss(options.triplet_weight), C[b.a].data(),
                             C[b.b].data(), &sigma[b.triplet]);
  if (options.pair_weight > 0.0) {
    for (size_t p = 0; p < pairs.size(); ++p) {
      const double length = (C[pairs[p].b] - C[pairs[p].a]).norm();
      if (!(length > 0.0)) continue;
      pair_sigma[p] = 1.0 / length;
      problem.AddResidualBlock(ScaledBaselineError::Create(pairs[p].u), loss(options.pair_weight), C[pairs[p].a].data(),
                               C[pairs[p].b].data(), &pair_sigma[p]);
      problem.SetParameterLowerBound(&pair_sigma[p], 0, 1e-3 * pair_sigma[p]);
    }
  }
  for (size_t t = 0; t < sizes->size(); ++t) {
    if (!problem.HasParameterBlock(&sigma[t])) continue;
    problem.SetParameterLowerBound(&sigma[t], 0, 1e-3 * sigma[t]);
  }
  if (problem.HasParameterBlock(C[fixed_node].data())) problem.SetParameterBlockConstant(C[fixed_node].data());
  if (problem.HasParameterBlock(&sigma[fixed_triplet])) problem.SetParameterBlockConstant(&sigma[fixed_triplet]);

  // The inverse scales are eliminated first (each touches two centres): the reduced system is
  // over the centres only. Eigen's sparse Cholesky is single-threaded, hence deterministic.
  ceres::Solver::Options solver_options = CeresSolverOptions(options.refine_solver);
  {
    auto ordering = std::make_shared<ceres::ParameterBlockOrdering>();
    for (double& s : inverse_scales)
      if (problem.HasParameterBlock(&s)) ordering->AddElementToGroup(&s, 0);
    for (Eigen::Vector3d& c : C)
      if (problem.HasParameterBlock(c.data())) ordering->AddElementToGroup(c.data(), 1);
    solver_options.linear_solver_ordering = ordering;
  }
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, &problem, &summary);

  for (int i = 0; i < n; ++i) centres->row(i) = C[i].transpose();
  for (size_t t = 0; t < sizes->size(); ++t) (*sizes)[t] = 1.0 / sigma[t];
  return static_cast<int>(summary.iterations.size());
}

}  // namespace pgba
