// From the local bundle problem to the camera reduced matrix (paper eqs. 2-3) and its
// eigen decomposition (paper eq. 5).
#pragma once

#include "modules/local_hessian/local_bundle.h"
#include "modules/local_hessian/local_hessian.h"

#include <Eigen/Cholesky>

namespace pgba {

struct ReducedCameraSystem {
  Eigen::MatrixXd h;        // H_cc - H_cp H_pp^-1 H_pc (6N + K square: poses, then intrinsics)
  Eigen::VectorXd g;        // g_c - H_cp H_pp^-1 g_p
  int num_points_used = 0;  // points whose H_pp was invertible
};

// Normal equations H = J^T W J of the weighted, robustified reprojection residuals (IRLS
// weights observation_weight * rho'(|r|^2) from the problem's loss object, exactly what
// Ceres' loss correction does for Huber and Cauchy) at the problem's current state, Schur-complemented on the points one 3x3
// block at a time (paper eq. 3), without ever forming the dense H_pp^-1. The poses must be
// linearised (omega = 0) so that h is in the chart centred at them. A point whose H_pp is
// singular contributes through the pseudo-inverse. The pose prior of the problem, if any, is
// not included (see AddGaugePrior).
ReducedCameraSystem ReducedCameraMatrix(const LocalBundleProblem& problem);

// The prior that fixes the 7-dim similarity gauge of h ("all extrinsics observed"), and the
// rank test of the motion.
struct GaugePrior {
  Eigen::MatrixXd P;  // added to h
  Eigen::MatrixXd F;  // P = F F^T up to rounding (7 columns for kSimilarity, diagonal for kIsotropic)
  double mu = 0.0;
  // (6N-7)-th largest / largest eigenvalue of h (before the prior) in the chart used for mu.
  double eigenvalue_ratio = 0.0;
};

// The directions h cannot see: the infinitesimal similarities of the local frame acting on
// the poses (translation, rotation about the centroid of the centres, scale about it), in
// the chart [c / L, omega] (L = 1 for the plain chart); 6N x 7, not orthonormal.
Eigen::Matrix<double, Eigen::Dynamic, 7> SimilarityGenerators(const std::vector<PoseBlock>& poses, double L);

// mu = prior_relative * lambda_max, lambda_max the largest eigenvalue of h in the chart
// [c / L, omega] (L = depth_scale if options.prior_scale_aware, else 1). P = mu I
// (kIsotropic) or mu times the orthogonal projector onto SimilarityGenerators
// (kSimilarity), in that chart, mapped back to [c, omega].
GaugePrior ComputeGaugePrior(const Eigen::MatrixXd& h, const std::vector<PoseBlock>& poses, double depth_scale,
                             const LocalHessianOptions& options);

// h = V^T diag(D)^2 V (paper eq. 5): rows of V orthonormal eigenvectors, eigenvalues
// ascending, negative ones (rounding) clamped to 0 before the square root.
void DecomposeReducedMatrix(const Eigen::MatrixXd& h, Eigen::MatrixXd* V, Eigen::VectorXd* D);

// h = P^T L diag(d) L^T P (pivoted LDL^T): V = L^T P, D = sqrt(max(d, 0)); returns the
// factorisation for solves.
Eigen::LDLT<Eigen::MatrixXd> FactorReducedMatrixLdlt(const Eigen::MatrixXd& h, Eigen::MatrixXd* V, Eigen::VectorXd* D);

// h^+ b for h = V^T diag(D)^2 V: eigenvalues below 1e-14 of the largest count as zero.
Eigen::VectorXd PseudoInverseSolve(const Eigen::MatrixXd& V, const Eigen::VectorXd& D, const Eigen::VectorXd& b);

}  // namespace pgba
