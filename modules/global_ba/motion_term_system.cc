#include "modules/global_ba/motion_term_system.h"

#include <Eigen/Cholesky>

namespace pgba::internal {

std::vector<const double*> PosePointers(const MotionBlockProblem& p, const MotionBlockTerm& t) {
  std::vector<const double*> out;
  for (const int i : t.poses) out.push_back(p.poses[i]->x.data());
  return out;
}

std::vector<const double*> IntrinsicPointers(const MotionBlockProblem& p, const MotionBlockTerm& t) {
  std::vector<const double*> out;
  for (const int i : t.intrinsics) out.push_back(p.intrinsics[i]->data());
  return out;
}

namespace {

// The motion's residual linearised at the current state: per view J_k = d dx_k / d[pose_k, sim]
// (6 x 13) and u = W^T (W dx - offset), the gradient of 1/2 |r|^2 with respect to dx.
struct ResidualLinearization {
  std::vector<Eigen::Matrix<double, 6, 13>> J;
  Eigen::VectorXd u;
};

ResidualLinearization LinearizeResidual(const MotionBlockProblem& p, const MotionBlockTerm& t) {
  ResidualLinearization r;
  Eigen::VectorXd dx;
  t.residual->Linearize(PosePointers(p, t), t.sim, IntrinsicPointers(p, t), &dx, &r.J);
  r.u = t.residual->DeviationGradient(dx);
  return r;
}

// h B over the pose rows (6N x 7), column block by column block: O(N^2).
Eigen::Matrix<double, Eigen::Dynamic, 7> HessianTimesSimilarityJacobian(const Eigen::MatrixXd& h,
                                                                        const ResidualLinearization& r) {
  const int n = static_cast<int>(r.J.size());
  Eigen::Matrix<double, Eigen::Dynamic, 7> hB = Eigen::Matrix<double, Eigen::Dynamic, 7>::Zero(6 * n, 7);
  for (int l = 0; l < n; ++l) hB.noalias() += h.block(0, 6 * l, 6 * n, 6) * r.J[l].rightCols<7>();
  return hB;
}

// weight x (B^T h B, B^T u): the similarity's block of the normal equations, added to Hss, gs.
void AddSimilarityBlock(const ResidualLinearization& r, const Eigen::Matrix<double, Eigen::Dynamic, 7>& hB,
                        double weight, Matrix7d* Hss, Vector7d* gs) {
  for (size_t k = 0; k < r.J.size(); ++k) {
    Hss->noalias() += weight * r.J[k].rightCols<7>().transpose() * hB.middleRows<6>(6 * k);
    gs->noalias() += weight * r.J[k].rightCols<7>().transpose() * r.u.segment<6>(6 * k);
  }
}

}  // namespace

TermSystem Linearize(const MotionBlockProblem& p, const MotionBlockTerm& t, const Eigen::MatrixXd& h) {
  TermSystem s;
  const int n = static_cast<int>(t.poses.size());
  const int K = t.residual->num_intrinsics();
  const ResidualLinearization r = LinearizeResidual(p, t);
  const Eigen::VectorXd& u = r.u;
  s.A.resize(n);
  s.B.resize(n);
  for (int k = 0; k < n; ++k) {
    s.A[k] = r.J[k].leftCols<6>();
    s.B[k] = r.J[k].rightCols<7>();
  }
  // h A over the pose rows, column block by column block: O(N^2).
  Eigen::MatrixXd hA(6 * n, 6 * n);
  for (int l = 0; l < n; ++l) hA.middleCols<6>(6 * l).noalias() = h.block(0, 6 * l, 6 * n, 6) * s.A[l];
  const Eigen::Matrix<double, Eigen::Dynamic, 7> hB = HessianTimesSimilarityJacobian(h, r);
  s.Hpp.resize(n * n);
  s.Hps.resize(6 * n, 7);
  s.Hss.setZero();
  s.gp.resize(6 * n);
  s.gs.setZero();
  s.Hpk.resize(6 * n, K);
  s.Hsk = Eigen::Matrix<double, 7, Eigen::Dynamic>::Zero(7, K);
  AddSimilarityBlock(r, hB, t.weight, &s.Hss, &s.gs);
  for (int k = 0; k < n; ++k) {
    for (int l = 0; l < n; ++l) s.Hpp[k * n + l].noalias() = t.weight * s.A[k].transpose() * hA.block<6, 6>(6 * k, 6 * l);
    s.Hps.middleRows<6>(6 * k).noalias() = t.weight * s.A[k].transpose() * hB.middleRows<6>(6 * k);
    s.gp.segment<6>(6 * k).noalias() = t.weight * s.A[k].transpose() * u.segment<6>(6 * k);
    if (K > 0) {
      const auto h_pk = h.block(6 * k, 6 * n, 6, K);
      s.Hpk.middleRows<6>(6 * k).noalias() = t.weight * s.A[k].transpose() * h_pk;
      s.Hsk.noalias() += t.weight * s.B[k].transpose() * h_pk;
    }
  }
  s.Hkk = t.weight * h.bottomRightCorner(K, K);
  s.gk = t.weight * u.tail(K);
  return s;
}

void OptimizeSimilarity(const MotionBlockProblem& p, const MotionBlockTerm& t, const Eigen::MatrixXd& h,
                        int iterations) {
  Eigen::Map<Vector7d> sim(t.sim);
  double cost = t.residual->SquaredNorm(PosePointers(p, t), t.sim, IntrinsicPointers(p, t));
  for (int it = 0; it < iterations; ++it) {
    const ResidualLinearization r = LinearizeResidual(p, t);
    Matrix7d Hss = Matrix7d::Zero();
    Vector7d gs = Vector7d::Zero();
    AddSimilarityBlock(r, HessianTimesSimilarityJacobian(h, r), 1.0, &Hss, &gs);
    const Vector7d saved = sim;
    sim -= Hss.ldlt().solve(gs);
    const double trial = t.residual->SquaredNorm(PosePointers(p, t), t.sim, IntrinsicPointers(p, t));
    if (!(trial < cost)) {
      sim = saved;
      return;
    }
    cost = trial;
  }
}


}  // namespace pgba::internal
