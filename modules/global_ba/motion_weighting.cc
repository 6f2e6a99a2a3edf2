#include "modules/global_ba/motion_weighting.h"

#include <cmath>

namespace pgba {

Eigen::MatrixXd MotionWeightMatrix(const LocalHessian& hessian, const GlobalBAOptions& options) {
  if (options.weighting == TripletWeighting::kHessian) return hessian.D.asDiagonal() * hessian.V;
  Eigen::VectorXd w(6 * hessian.num_views());
  const double wp = 1.0 / (options.scalar_position_sigma * hessian.depth_scale);
  const double wr = 1.0 / options.scalar_rotation_sigma;
  for (int k = 0; k < hessian.num_views(); ++k) w.segment<6>(6 * k) << wp, wp, wp, wr, wr, wr;
  return w.asDiagonal();
}

double ResidualUnit(const LocalHessian& hessian, const GlobalBAOptions& options) {
  return options.weighting == TripletWeighting::kHessian ? std::sqrt(hessian.observation_weight) : 1.0;
}

double IrlsWeight(double error, double sigma, double factor) {
  if (!(factor > 0) || !(sigma > 0)) return 1.0;
  const double u = error / (factor * sigma);
  return 1.0 / (1.0 + u * u);
}

}  // namespace pgba
