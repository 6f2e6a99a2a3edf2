#include "modules/local_hessian/reduced_camera_matrix.h"

#include <ceres/jet.h>

#include <Eigen/Eigenvalues>
#include <Eigen/QR>
#include <cmath>

#include "pgba/geometry/rotation.h"

namespace pgba {

namespace {

using Jet9 = ceres::Jet<double, 9>;

// Residual (pixels) of one observation and its Jacobians w.r.t. the pose 6-vector and the
// point, through the shared ReprojectionError functor.
void ObservationJacobian(const LocalBundleProblem& p, const LocalObservation& o, Eigen::Vector2d* r,
                         Eigen::Matrix<double, 2, 6>* Jc, Eigen::Matrix<double, 2, 3>* Jp) {
  const PoseBlock& b = p.poses[o.view];
  Jet9 pose[6], X[3], res[2];
  for (int i = 0; i < 6; ++i) pose[i] = Jet9(b.x(i), i);
  for (int i = 0; i < 3; ++i) X[i] = Jet9(p.points[o.point](i), 6 + i);
  const ReprojectionError f(p.cameras[o.view], b.R0, o.pixel);
  f(pose, X, res);
  for (int k = 0; k < 2; ++k) {
    (*r)(k) = res[k].a;
    Jc->row(k) = res[k].v.head<6>().transpose();
    Jp->row(k) = res[k].v.tail<3>().transpose();
  }
}

// Pseudo-inverse of a symmetric PSD 3x3 block (a point seen under a tiny angle has a nearly
// singular H_pp; the pseudo-inverse is the Schur complement's limit there).
bool PseudoInverse3(const Eigen::Matrix3d& A, Eigen::Matrix3d* inv) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(A);
  if (es.info() != Eigen::Success) return false;
  const Eigen::Vector3d ev = es.eigenvalues();
  if (!(ev(2) > 0)) return false;
  Eigen::Vector3d d;
  for (int i = 0; i < 3; ++i) d(i) = ev(i) > 1e-12 * ev(2) ? 1.0 / ev(i) : 0.0;
  *inv = es.eigenvectors() * d.asDiagonal() * es.eigenvectors().transpose();
  return true;
}

}  // namespace

ReducedCameraSystem ReducedCameraMatrix(const LocalBundleProblem& p) {
  ReducedCameraSystem out;
  const double huber2 = p.huber_px * p.huber_px;
  size_t begin = 0;
  while (begin < p.observations.size()) {
    size_t end = begin;
    while (end < p.observations.size() && p.observations[end].point == p.observations[begin].point) ++end;
    Eigen::Matrix3d Hpp = Eigen::Matrix3d::Zero();
    Eigen::Vector3d gp = Eigen::Vector3d::Zero();
    Eigen::Matrix<double, 18, 3> Hcp = Eigen::Matrix<double, 18, 3>::Zero();
    for (size_t i = begin; i < end; ++i) {
      const LocalObservation& o = p.observations[i];
      Eigen::Vector2d r;
      Eigen::Matrix<double, 2, 6> Jc;
      Eigen::Matrix<double, 2, 3> Jp;
      ObservationJacobian(p, o, &r, &Jc, &Jp);
      // IRLS weight of Huber: rho'(s) = 1 inside, delta / |r| outside (rho'' <= 0 there, so
      // Ceres' corrector reduces to this too), times the attenuation.
      const double s = r.squaredNorm();
      const double w = p.observation_weight * o.weight * (s <= huber2 ? 1.0 : p.huber_px / std::sqrt(s));
      const int c = 6 * o.view;
      out.h.block<6, 6>(c, c) += w * Jc.transpose() * Jc;
      out.g.segment<6>(c) += w * Jc.transpose() * r;
      Hcp.middleRows<6>(c) += w * Jc.transpose() * Jp;
      Hpp += w * Jp.transpose() * Jp;
      gp += w * Jp.transpose() * r;
    }
    Eigen::Matrix3d Hpp_inv;
    if (PseudoInverse3(Hpp, &Hpp_inv)) {
      out.h -= Hcp * Hpp_inv * Hcp.transpose();
      out.g -= Hcp * (Hpp_inv * gp);
      ++out.num_points_used;
    }
    begin = end;
  }
  // Symmetrise the rounding of the subtractions.
  out.h = 0.5 * (out.h + out.h.transpose()).eval();
  return out;
}

Eigen::Matrix<double, 18, 7> SimilarityGenerators(const std::array<PoseBlock, 3>& poses, double L) {
  // X' = (1 + s) Exp(theta) (X - g) + g + t maps c_k to c_k + t + theta x (c_k - g) + s (c_k - g)
  // and r_k to r_k Exp(-theta), i.e. omega_k to omega_k - theta (first order).
  const Eigen::Vector3d g = (poses[0].x.head<3>() + poses[1].x.head<3>() + poses[2].x.head<3>()) / 3.0;
  Eigen::Matrix<double, 18, 7> G = Eigen::Matrix<double, 18, 7>::Zero();
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d d = poses[k].x.head<3>() - g;
    G.block<3, 3>(6 * k, 0) = Eigen::Matrix3d::Identity() / L;
    G.block<3, 3>(6 * k, 3) = -Skew(d) / L;  // theta x d = -[d]_x theta
    G.block<3, 3>(6 * k + 3, 3) = -Eigen::Matrix3d::Identity();
    G.block<3, 1>(6 * k, 6) = d / L;
  }
  return G;
}

GaugePrior ComputeGaugePrior(const Matrix18d& h, const std::array<PoseBlock, 3>& poses, double depth_scale,
                             const LocalHessianOptions& options) {
  GaugePrior prior;
  const double L = options.prior_scale_aware && depth_scale > 0 ? depth_scale : 1.0;
  Vector18d s;  // [c, omega] = diag(s) [c / L, omega]
  for (int k = 0; k < 3; ++k) s.segment<6>(6 * k) << L, L, L, 1.0, 1.0, 1.0;
  const Matrix18d hs = s.asDiagonal() * h * s.asDiagonal();
  Eigen::SelfAdjointEigenSolver<Matrix18d> es(hs, Eigen::EigenvaluesOnly);
  if (es.info() != Eigen::Success) return prior;
  const Vector18d ev = es.eigenvalues();  // ascending
  const double lmax = ev(17);
  if (!(lmax > 0) || !std::isfinite(lmax)) return prior;
  // 18 - 7 = 11 directions are not similarities of the local frame; the weakest is ev(7).
  prior.eigenvalue_ratio = ev(7) / lmax;
  prior.mu = options.prior_relative * lmax;
  Matrix18d Ps;  // in the scaled chart
  if (options.prior_shape == PriorShape::kIsotropic) {
    Ps = prior.mu * Matrix18d::Identity();
  } else {
    const Eigen::HouseholderQR<Eigen::Matrix<double, 18, 7>> qr(SimilarityGenerators(poses, L));
    const Eigen::Matrix<double, 18, 7> Q = qr.householderQ() * Eigen::Matrix<double, 18, 7>::Identity();
    Ps = prior.mu * Q * Q.transpose();
  }
  const Vector18d inv_s = s.cwiseInverse();
  prior.P = inv_s.asDiagonal() * Ps * inv_s.asDiagonal();
  return prior;
}

void DecomposeReducedMatrix(const Matrix18d& h, Matrix18d* V, Vector18d* D) {
  Eigen::SelfAdjointEigenSolver<Matrix18d> es(h);
  *V = es.eigenvectors().transpose();
  *D = es.eigenvalues().cwiseMax(0.0).cwiseSqrt();
}

}  // namespace pgba
