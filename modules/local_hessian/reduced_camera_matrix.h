// From the local bundle problem to the camera reduced matrix (paper eqs. 2-3) and its
// eigen decomposition (paper eq. 5).
#pragma once

#include "modules/local_hessian/local_bundle.h"
#include "modules/local_hessian/local_hessian.h"

namespace pgba {

struct ReducedCameraSystem {
  Matrix18d h = Matrix18d::Zero();  // H_cc - H_cp H_pp^-1 H_pc
  Vector18d g = Vector18d::Zero();  // g_c - H_cp H_pp^-1 g_p
  int num_points_used = 0;          // points whose H_pp was invertible
};

// Normal equations H = J^T W J of the weighted, Huber-robustified reprojection residuals
// (IRLS weights observation_weight * rho'(|r|^2), exactly what Ceres' loss correction does
// for Huber) at the problem's current state, Schur-complemented on the points one 3x3
// block at a time (paper eq. 3), without ever forming the dense H_pp^-1. The poses must be
// linearised (omega = 0) so that h is in the chart centred at them. A point whose H_pp is
// singular contributes through the pseudo-inverse. The pose prior of the problem, if any, is
// not included (see AddGaugePrior).
ReducedCameraSystem ReducedCameraMatrix(const LocalBundleProblem& problem);

// The weak prior that fixes the 7-dim similarity gauge of h ("all three extrinsics
// observed"), and the rank test of the triplet.
struct GaugePrior {
  double position = 0.0;  // mu_c added to each centre coordinate
  double rotation = 0.0;  // mu_omega added to each rotation coordinate
  // 11th largest / largest eigenvalue of h (before the prior) in the chart used for mu.
  double eigenvalue_ratio = 0.0;
};

// mu_omega = prior_relative * lambda_max and mu_c = mu_omega / L^2, the eigenvalue taken in
// the chart [c / L, omega] (L = depth_scale) if options.prior_scale_aware; otherwise
// mu_c = mu_omega = prior_relative * lambda_max(h).
GaugePrior ComputeGaugePrior(const Matrix18d& h, double depth_scale, const LocalHessianOptions& options);

// h + diag(mu_c I3, mu_omega I3, ...) over the three views.
Matrix18d AddGaugePrior(const Matrix18d& h, const GaugePrior& prior);

// h = V^T diag(D)^2 V (paper eq. 5): rows of V orthonormal eigenvectors, eigenvalues
// ascending, negative ones (rounding) clamped to 0 before the square root.
void DecomposeReducedMatrix(const Matrix18d& h, Matrix18d* V, Vector18d* D);

}  // namespace pgba
