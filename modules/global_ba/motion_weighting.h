// Weights of the global BA's motion residuals: the square-root information W_s (the
// pointless BA's D_s V_s or Aver_BA's scalars) and the IRLS weight from the fitting error.
#pragma once

#include "modules/global_ba/global_ba.h"
#include "modules/global_ba/motion_weight.h"

namespace pgba {

// W_s with W_s (x_s - x0_s) the triplet's residual. kHessian: W_s^T W_s = h_s, through h_s
// itself (borrowed: the hessian must outlive the weight), or with `factored` as D_s V_s
// (paper eq. 5; LocalHessian::Factor, computed here), for a residual vector (the Ceres
// solver); kScalar: diagonal 1 / (scalar_position_sigma L_s) on positions,
// 1 / scalar_rotation_sigma on rotations (L_s the median point depth of the triplet,
// LocalHessian::depth_scale).
MotionWeight MotionWeightOf(const LocalHessian& hessian, const GlobalBAOptions& options, bool factored = false);

// |W_s dx| that a 1 px error of every observation would leave: sqrt(gamma/M) for kHessian
// (h carries the attenuation), 1 for kScalar. Fitting errors divided by it are comparable
// across triplets.
double ResidualUnit(const LocalHessian& hessian, const GlobalBAOptions& options);

// Cauchy IRLS weight 1 / (1 + (e / (factor sigma))^2) (LossFunctionOptions::IrlsWeight);
// 1 if factor <= 0 or sigma <= 0.
double IrlsWeight(double error, double sigma, double factor);

}  // namespace pgba
