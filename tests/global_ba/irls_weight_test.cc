// The global BA's IRLS weight on a motion's fitting error (motion_weighting.h): Cauchy with
// scale c = factor * sigma, i.e. rho(s) = c^2 log(1 + s / c^2) of s = e^2, whose weight is
// rho'(s) = 1 / (1 + s / c^2). Checked against Ceres' CauchyLoss (the loss the IRLS stands
// in for) and against central differences of rho, at errors on both sides of c; switched
// off (weight 1) by a non-positive factor or sigma.
#include "modules/global_ba/motion_weighting.h"

#include <ceres/loss_function.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace pgba {
namespace {

TEST(GlobalBAIrlsWeight, IsCauchyRhoPrimeOfTheSquaredError) {
  for (const double sigma : {0.3, 1.0, 2.5})
    for (const double factor : {1.0, 2.0, 4.0}) {
      const double c = factor * sigma;
      const ceres::CauchyLoss cauchy(c);
      for (const double e : {0.0, 0.1, 0.5, 1.0, 2.0, 3.0, 7.5, 40.0}) {
        double rho[3];
        cauchy.Evaluate(e * e, rho);
        EXPECT_NEAR(IrlsWeight(e, sigma, factor), rho[1], 1e-15) << e << " " << sigma << " " << factor;
        EXPECT_DOUBLE_EQ(IrlsWeight(-e, sigma, factor), IrlsWeight(e, sigma, factor));
        // rho'(s) by central differences of the definition.
        const auto r = [c](double s) { return c * c * std::log1p(s / (c * c)); };
        const double s = e * e, h = 1e-6 * std::max(s, 1.0);
        const double numeric = (r(s + h) - r(s - h)) / (2 * h);  // log1p is smooth through s = 0
        EXPECT_NEAR(IrlsWeight(e, sigma, factor), numeric, 1e-6) << e;
      }
      // At e = c the weight is exactly one half.
      EXPECT_DOUBLE_EQ(IrlsWeight(c, sigma, factor), 0.5);
    }
}

TEST(GlobalBAIrlsWeight, OffWithoutAScale) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const double e : {0.0, 1.0, 100.0}) {
    EXPECT_EQ(IrlsWeight(e, 1.0, 0.0), 1.0);
    EXPECT_EQ(IrlsWeight(e, 1.0, -2.0), 1.0);
    EXPECT_EQ(IrlsWeight(e, 0.0, 2.0), 1.0);
    EXPECT_EQ(IrlsWeight(e, nan, 2.0), 1.0);
    EXPECT_EQ(IrlsWeight(e, 1.0, nan), 1.0);
  }
}

}  // namespace
}  // namespace pgba
