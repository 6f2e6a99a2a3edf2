#include "modules/local_hessian/reduced_camera_matrix.h"

#include <ceres/jet.h>
#include <ceres/loss_function.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/QR>
#include <cmath>
#include <memory>

#include "pgba/geometry/rotation.h"
#include "pgba/optim/intrinsics.h"

namespace pgba {

namespace {

using Jet9 = ceres::Jet<double, 9>;
constexpr int kMaxParams = 8;  // OPENCV
using Jet17 = ceres::Jet<double, 9 + kMaxParams>;

// Residual (pixels) of one observation and its Jacobians w.r.t. the pose 6-vector, the point
// and (for a view of a free camera) the camera's free intrinsics, through the shared
// reprojection functors.
void ObservationJacobian(const LocalBundleProblem& p, const LocalObservation& o, Eigen::Vector2d* r,
                         Eigen::Matrix<double, 2, 6>* Jc, Eigen::Matrix<double, 2, 3>* Jp, Eigen::MatrixXd* Jk) {
  const PoseBlock& b = p.poses[o.view];
  const int c = p.view_intrinsics[o.view];
  if (c < 0) {
    Jet9 pose[6], X[3], res[2];
    for (int i = 0; i < 6; ++i) pose[i] = Jet9(b.x(i), i);
    for (int i = 0; i < 3; ++i) X[i] = Jet9(p.points[o.point](i), 6 + i);
    const ReprojectionError f(p.cameras[o.view], b.R0, o.pixel);
    f(pose, X, res);
    for (int k = 0; k < 2; ++k) {
      (*r)(k) = res[k].a;
      Jc->row(k) = res[k].v.head<6>().transpose();
      Jp->row(k) = res[k].v.segment<3>(6).transpose();
    }
    return;
  }
  const Camera& camera = p.intrinsics.cameras[c];
  const std::vector<int>& free = p.intrinsics.free[c];
  const Eigen::MatrixXd& directions = p.intrinsics.directions[c];
  Jet17 pose[6], X[3], params[kMaxParams], res[2];
  for (int i = 0; i < 6; ++i) pose[i] = Jet17(b.x(i), i);
  for (int i = 0; i < 3; ++i) X[i] = Jet17(p.points[o.point](i), 6 + i);
  for (size_t i = 0; i < camera.params.size(); ++i) {
    params[i] = Jet17(camera.params[i]);
    params[i].v.segment(9, free.size()) = directions.row(static_cast<int>(i)).transpose();
  }
  const ReprojectionErrorWithIntrinsics f(camera.model, b.R0, o.pixel, 1.0);
  f(pose, X, params, res);
  Jk->resize(2, static_cast<int>(free.size()));
  for (int k = 0; k < 2; ++k) {
    (*r)(k) = res[k].a;
    Jc->row(k) = res[k].v.head<6>().transpose();
    Jp->row(k) = res[k].v.segment<3>(6).transpose();
    Jk->row(k) = res[k].v.segment(9, free.size()).transpose();
  }
}

// Pseudo-inverse of a symmetric PSD 3x3 block (a point seen under a tiny angle has a nearly
// singular H_pp; the pseudo-inverse is the Schur complement's limit there).
bool PseudoInverse3(const Eigen::Matrix3d& A, Eigen::Matrix3d* inv) {
  // Well conditioned (the common case), the pseudo-inverse is the inverse: no eigenvalue is
  // below the cut. trace(A) trace(A^-1) bounds the condition number from above, so a bound
  // under 1e10 proves it; otherwise (or if A is not positive definite) the eigen path decides.
  const Eigen::LLT<Eigen::Matrix3d> llt(A);
  if (llt.info() == Eigen::Success) {
    const Eigen::Matrix3d Ainv = llt.solve(Eigen::Matrix3d::Identity());
    const double bound = A.trace() * Ainv.trace();
    if (std::isfinite(bound) && bound > 0 && bound < 1e10) {
      *inv = 0.5 * (Ainv + Ainv.transpose());
      return true;
    }
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(A);
  if (es.info() != Eigen::Success) return false;
  const Eigen::Vector3d ev = es.eigenvalues();
  if (!(ev(2) > 0)) return false;
  Eigen::Vector3d d;
  for (int i = 0; i < 3; ++i) d(i) = ev(i) > 1e-12 * ev(2) ? 1.0 / ev(i) : 0.0;
  *inv = es.eigenvectors() * d.asDiagonal() * es.eigenvectors().transpose();
  return true;
}

// Largest eigenvalue of a symmetric PSD matrix by power iterations from a fixed start (to
// ~1e-3 relative: mu is a small multiple of it), O(n^2) per iteration.
double LargestEigenvalue(const Eigen::MatrixXd& A) {
  Eigen::VectorXd v = Eigen::VectorXd::Ones(A.rows()).normalized();
  double lambda = 0.0;
  for (int i = 0; i < 50; ++i) {
    const Eigen::VectorXd w = A * v;
    const double next = v.dot(w);
    const double norm = w.norm();
    if (!(norm > 0)) return 0.0;
    v = w / norm;
    if (i > 5 && std::abs(next - lambda) <= 1e-4 * std::abs(next)) return next;
    lambda = next;
  }
  return lambda;
}

}  // namespace

ReducedCameraSystem ReducedCameraMatrix(const LocalBundleProblem& p) {
  ReducedCameraSystem out;
  const int n = p.num_unknowns();
  const int n_poses = 6 * p.num_views();
  out.h = Eigen::MatrixXd::Zero(n, n);
  out.g = Eigen::VectorXd::Zero(n);
  Eigen::Matrix<double, Eigen::Dynamic, 3> Hcp(n, 3);
  // IRLS weight of the loss: rho'(s) of the squared error s, as Ceres' loss correction takes
  // it where rho'' <= 0 (Huber's linear part, Cauchy everywhere).
  const std::unique_ptr<ceres::LossFunction> loss(p.loss.CreateLossFunction());
  // The rows a point touches: its views' pose blocks, then its free cameras' intrinsics
  // (a camera shared by several of its views once).
  struct Segment {
    int row, size;
  };
  std::vector<Segment> segments;
  size_t begin = 0;
  while (begin < p.observations.size()) {
    size_t end = begin;
    while (end < p.observations.size() && p.observations[end].point == p.observations[begin].point) ++end;
    Eigen::Matrix3d Hpp = Eigen::Matrix3d::Zero();
    Eigen::Vector3d gp = Eigen::Vector3d::Zero();
    Hcp.setZero();
    segments.clear();
    for (size_t i = begin; i < end; ++i) {
      const LocalObservation& o = p.observations[i];
      Eigen::Vector2d r;
      Eigen::Matrix<double, 2, 6> Jc;
      Eigen::Matrix<double, 2, 3> Jp;
      Eigen::MatrixXd Jk;
      ObservationJacobian(p, o, &r, &Jc, &Jp, &Jk);
      double rho[3] = {0.0, 1.0, 0.0};
      if (loss) loss->Evaluate(r.squaredNorm(), rho);
      const double w = p.observation_weight * o.weight * rho[1];
      const int c = 6 * o.view;
      out.h.block<6, 6>(c, c) += w * Jc.transpose() * Jc;
      out.g.segment<6>(c) += w * Jc.transpose() * r;
      Hcp.middleRows<6>(c) += w * Jc.transpose() * Jp;
      Hpp += w * Jp.transpose() * Jp;
      gp += w * Jp.transpose() * r;
      segments.push_back({c, 6});
      if (const int ci = p.view_intrinsics[o.view]; ci >= 0) {
        const int k = n_poses + p.intrinsics.offset[ci], nk = static_cast<int>(Jk.cols());
        out.h.block(k, k, nk, nk) += w * Jk.transpose() * Jk;
        out.h.block(c, k, 6, nk) += w * Jc.transpose() * Jk;
        out.h.block(k, c, nk, 6) += w * Jk.transpose() * Jc;
        out.g.segment(k, nk) += w * Jk.transpose() * r;
        Hcp.middleRows(k, nk) += w * Jk.transpose() * Jp;
        bool seen = false;
        for (const Segment& sg : segments) seen = seen || sg.row == k;
        if (!seen) segments.push_back({k, nk});
      }
    }
    Eigen::Matrix3d Hpp_inv;
    if (PseudoInverse3(Hpp, &Hpp_inv)) {
      // Only the rows of this point: H_cp is zero elsewhere (a 6N x 6N product per point
      // would make long motions quadratic in N for nothing). Only the blocks on and above the
      // diagonal: h is symmetrised below, 0.5 (h + h^T), so an off-diagonal block subtracted
      // twice above it and not at all below gives the same h at a third of the products
      // (the pose-pose blocks of a track of L views are L^2 of them; long whole-track motions).
      for (const Segment& a : segments) {
        if (a.size == 6) {  // pose rows: fixed-size products (the hot loop)
          const Eigen::Matrix<double, 6, 3> T = Hcp.middleRows<6>(a.row) * Hpp_inv;
          const Eigen::Matrix<double, 6, 3> T2 = 2.0 * T;
          for (const Segment& b : segments) {
            if (b.row < a.row) continue;
            const Eigen::Matrix<double, 6, 3>& Ta = b.row == a.row ? T : T2;
            if (b.size == 6) {
              out.h.block<6, 6>(a.row, b.row).noalias() -= Ta * Hcp.middleRows<6>(b.row).transpose();
            } else {
              out.h.block(a.row, b.row, 6, b.size).noalias() -= Ta * Hcp.middleRows(b.row, b.size).transpose();
            }
          }
          continue;
        }
        const Eigen::MatrixXd T = Hcp.middleRows(a.row, a.size) * Hpp_inv;
        for (const Segment& b : segments) {
          if (b.row < a.row) continue;
          const double twice = b.row == a.row ? 1.0 : 2.0;
          out.h.block(a.row, b.row, a.size, b.size).noalias() -= (twice * T) * Hcp.middleRows(b.row, b.size).transpose();
        }
      }
      out.g -= Hcp * (Hpp_inv * gp);
      ++out.num_points_used;
    }
    begin = end;
  }
  // Symmetrise the rounding of the subtractions.
  out.h = 0.5 * (out.h + out.h.transpose()).eval();
  return out;
}

Eigen::Matrix<double, Eigen::Dynamic, 7> SimilarityGenerators(const std::vector<PoseBlock>& poses, double L) {
  // X' = (1 + s) Exp(theta) (X - g) + g + t maps c_k to c_k + t + theta x (c_k - g) + s (c_k - g)
  // and r_k to r_k Exp(-theta), i.e. omega_k to omega_k - theta (first order).
  const int n = static_cast<int>(poses.size());
  Eigen::Vector3d g = Eigen::Vector3d::Zero();
  for (const PoseBlock& b : poses) g += b.x.head<3>() / n;
  Eigen::Matrix<double, Eigen::Dynamic, 7> G = Eigen::Matrix<double, Eigen::Dynamic, 7>::Zero(6 * n, 7);
  for (int k = 0; k < n; ++k) {
    const Eigen::Vector3d d = poses[k].x.head<3>() - g;
    G.block<3, 3>(6 * k, 0) = Eigen::Matrix3d::Identity() / L;
    G.block<3, 3>(6 * k, 3) = -Skew(d) / L;  // theta x d = -[d]_x theta
    G.block<3, 3>(6 * k + 3, 3) = -Eigen::Matrix3d::Identity();
    G.block<3, 1>(6 * k, 6) = d / L;
  }
  return G;
}

GaugePrior ComputeGaugePrior(const Eigen::MatrixXd& h, const std::vector<PoseBlock>& poses, double depth_scale,
                             const LocalHessianOptions& options) {
  GaugePrior prior;
  const int n = 6 * static_cast<int>(poses.size());
  // With intrinsic unknowns h has K more rows; the gauge (a similarity of the local frame)
  // leaves the intrinsics unchanged, so the prior has zeros there, and mu and the rank test
  // are taken on the pose block.
  const int total = static_cast<int>(h.rows());
  prior.P = Eigen::MatrixXd::Zero(std::max(total, n), std::max(total, n));
  prior.F = Eigen::MatrixXd::Zero(std::max(total, n), 0);
  if (total < n || h.cols() != total || n <= kGaugeDimension) return prior;
  const double L = options.prior_scale_aware && depth_scale > 0 ? depth_scale : 1.0;
  Eigen::VectorXd s(n);  // [c, omega] = diag(s) [c / L, omega]
  for (int k = 0; k < n / 6; ++k) s.segment<6>(6 * k) << L, L, L, 1.0, 1.0, 1.0;
  const Eigen::MatrixXd hs = s.asDiagonal() * h.topLeftCorner(n, n) * s.asDiagonal();
  double lmax = 0.0;
  if (options.min_eigenvalue_ratio > 0) {
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(hs, Eigen::EigenvaluesOnly);
    if (es.info() != Eigen::Success) return prior;
    const Eigen::VectorXd ev = es.eigenvalues();  // ascending
    lmax = ev(n - 1);
    // 6N - 7 directions are not similarities of the local frame; the weakest is ev(7).
    if (lmax > 0) prior.eigenvalue_ratio = ev(kGaugeDimension) / lmax;
  } else {
    lmax = LargestEigenvalue(hs);  // no rank test: the largest eigenvalue is all mu needs
  }
  if (!(lmax > 0) || !std::isfinite(lmax)) return prior;
  prior.mu = options.prior_relative * lmax;
  Eigen::MatrixXd Ps;  // in the scaled chart
  const Eigen::VectorXd inv_s = s.cwiseInverse();
  if (options.prior_shape == PriorShape::kIsotropic) {
    Ps = prior.mu * Eigen::MatrixXd::Identity(n, n);
    prior.F = Eigen::MatrixXd::Zero(prior.P.rows(), n);
    prior.F.topRows(n) = (std::sqrt(prior.mu) * inv_s).asDiagonal();
  } else {
    const Eigen::HouseholderQR<Eigen::MatrixXd> qr(SimilarityGenerators(poses, L));
    const Eigen::MatrixXd Q = qr.householderQ() * Eigen::MatrixXd::Identity(n, kGaugeDimension);
    Ps = prior.mu * Q * Q.transpose();
    prior.F = Eigen::MatrixXd::Zero(prior.P.rows(), kGaugeDimension);
    prior.F.topRows(n) = std::sqrt(prior.mu) * inv_s.asDiagonal() * Q;
  }
  prior.P.topLeftCorner(n, n) = inv_s.asDiagonal() * Ps * inv_s.asDiagonal();
  return prior;
}

void DecomposeReducedMatrix(const Eigen::MatrixXd& h, Eigen::MatrixXd* V, Eigen::VectorXd* D) {
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(h);
  *V = es.eigenvectors().transpose();
  *D = es.eigenvalues().cwiseMax(0.0).cwiseSqrt();
}

Eigen::LDLT<Eigen::MatrixXd> FactorReducedMatrixLdlt(const Eigen::MatrixXd& h, Eigen::MatrixXd* V, Eigen::VectorXd* D) {
  Eigen::LDLT<Eigen::MatrixXd> ldlt(h);
  const Eigen::MatrixXd Lt = ldlt.matrixU();  // L^T
  *V = Lt * ldlt.transpositionsP().transpose();  // L^T P (Eigen: h = P^T L D L^T P)
  *D = ldlt.vectorD().cwiseMax(0.0).cwiseSqrt();
  return ldlt;
}

Eigen::VectorXd PseudoInverseSolve(const Eigen::MatrixXd& V, const Eigen::VectorXd& D, const Eigen::VectorXd& b) {
  const Eigen::VectorXd lambda = D.cwiseAbs2();
  const double floor = 1e-14 * (lambda.size() > 0 ? lambda.maxCoeff() : 0.0);
  Eigen::VectorXd inv(lambda.size());
  for (int i = 0; i < lambda.size(); ++i) inv(i) = lambda(i) > floor ? 1.0 / lambda(i) : 0.0;
  return V.transpose() * (inv.asDiagonal() * (V * b));
}

}  // namespace pgba
