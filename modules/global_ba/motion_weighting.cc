#include "modules/global_ba/motion_weighting.h"

#include <algorithm>
#include <cmath>

#include "pgba/optim/loss_function_options.h"

namespace pgba {

MotionWeight MotionWeightOf(const LocalHessian& hessian, const GlobalBAOptions& options, bool factored) {
  if (options.weighting == TripletWeighting::kHessian) {
    // The local Hessian itself, not copied: it outlives every residual of the global BA.
    if (!factored) return MotionWeight::OfGram(hessian.h);
    auto V = std::make_shared<Eigen::MatrixXd>();
    auto D = std::make_shared<Eigen::VectorXd>();
    hessian.Factor(V.get(), D.get());
    return MotionWeight(std::move(D), std::move(V));
  }
  const int n = 6 * hessian.num_views();
  Eigen::VectorXd w(n + hessian.num_intrinsics());
  const double wp = 1.0 / (options.scalar_position_sigma * hessian.depth_scale);
  const double wr = 1.0 / options.scalar_rotation_sigma;
  for (int k = 0; k < hessian.num_views(); ++k) w.segment<6>(6 * k) << wp, wp, wp, wr, wr, wr;
  // Intrinsics (self-calibration): relative to their value as the rotations (a focal 1e-3
  // off moves the image like a 1e-3 rad rotation), distortion coefficients absolutely.
  for (int i = 0; i < hessian.num_intrinsics(); ++i)
    w(n + i) = wr / std::max(1.0, std::abs(hessian.intrinsics0(i)));
  return MotionWeight(std::make_shared<const Eigen::VectorXd>(std::move(w)), nullptr);
}

double ResidualUnit(const LocalHessian& hessian, const GlobalBAOptions& options) {
  return options.weighting == TripletWeighting::kHessian ? std::sqrt(hessian.observation_weight) : 1.0;
}

double IrlsWeight(double error, double sigma, double factor) {
  if (!(factor > 0) || !(sigma > 0)) return 1.0;
  return LossFunctionOptions{LossType::kCauchy, factor * sigma}.IrlsWeight(error);
}

}  // namespace pgba
