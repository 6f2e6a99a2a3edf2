// The IRLS weights of the averaging stage (robust_loss.h) against each loss's definition:
// w(r) = rho'(r) / r, with rho'(r) taken by central differences of rho written here, at
// residuals chosen on both sides of the scale (and both signs). Bounded-weight losses (L2,
// Huber, Geman-McClure) are normalised to w(0) = 1, so w(r) = (rho'(r) / r) / lim_0 rho'/r;
// L1 and l1/2 diverge at 0, so only ratios w(r) / w(r_ref) are defined by the loss (any
// constant factor cancels in the weighted least squares), and |r| is clamped at 1e-3 scale.
// Huber also against Ceres' HuberLoss: rho_ceres(s = r^2), w = rho_ceres'(r^2).
#include "averaging/robust_loss.h"

#include <ceres/loss_function.h>
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "pgba/util/error.h"

namespace pgba {
namespace {

constexpr double kScale = 0.7;

std::function<double(double)> Rho(RobustLoss loss) {
  const double s = kScale;
  switch (loss) {
    case RobustLoss::kL2:
      return [](double r) { return 0.5 * r * r; };
    case RobustLoss::kL1:
      return [](double r) { return std::abs(r); };
    case RobustLoss::kHuber:
      return [s](double r) { return std::abs(r) <= s ? 0.5 * r * r : s * std::abs(r) - 0.5 * s * s; };
    case RobustLoss::kGemanMcClure:
      return [s](double r) { return r * r / (r * r + s * s); };
    case RobustLoss::kLHalf:
      return [](double r) { return std::sqrt(std::abs(r)); };
  }
  return nullptr;
}

// rho'(r) / r by central differences.
double WeightByDefinition(RobustLoss loss, double r) {
  const auto rho = Rho(loss);
  const double h = 1e-6 * std::max(std::abs(r), 1e-3);
  return (rho(r + h) - rho(r - h)) / (2 * h) / r;
}

const std::vector<double> kResiduals = {-5.3, -0.9, -0.2, 0.05, 0.3, 0.69, 0.71, 1.4, 3.0, 12.0};

TEST(RobustLossWeights, BoundedLossesAreRhoPrimeOverRNormalisedAtZero) {
  for (const RobustLoss loss : {RobustLoss::kL2, RobustLoss::kHuber, RobustLoss::kGemanMcClure}) {
    const double w0 = WeightByDefinition(loss, 1e-4);  // lim_{r -> 0} rho'(r) / r
    EXPECT_NEAR(IrlsWeight(loss, 0.0, kScale), 1.0, 1e-12) << RobustLossName(loss);
    for (const double r : kResiduals)
      EXPECT_NEAR(IrlsWeight(loss, r, kScale), WeightByDefinition(loss, r) / w0, 1e-6)
          << RobustLossName(loss) << " r " << r;
  }
}

TEST(RobustLossWeights, UnboundedLossesHaveTheRatiosOfRhoPrimeOverR) {
  for (const RobustLoss loss : {RobustLoss::kL1, RobustLoss::kLHalf}) {
    const double ref = 1.0;
    for (const double r : kResiduals) {
      const double expected = WeightByDefinition(loss, r) / WeightByDefinition(loss, ref);
      const double got = IrlsWeight(loss, r, kScale) / IrlsWeight(loss, ref, kScale);
      EXPECT_NEAR(got / expected, 1.0, 1e-6) << RobustLossName(loss) << " r " << r;
    }
    // Below the floor 1e-3 scale the weight stops growing: that of |r| = 1e-3 scale.
    const double floor = 1e-3 * kScale;
    EXPECT_DOUBLE_EQ(IrlsWeight(loss, 1e-9, kScale), IrlsWeight(loss, floor, kScale)) << RobustLossName(loss);
    EXPECT_DOUBLE_EQ(IrlsWeight(loss, 0.0, kScale), IrlsWeight(loss, floor, kScale)) << RobustLossName(loss);
    EXPECT_NEAR(IrlsWeight(loss, floor, kScale) / IrlsWeight(loss, ref, kScale),
                WeightByDefinition(loss, floor) / WeightByDefinition(loss, ref), 1e-6 * IrlsWeight(loss, floor, kScale))
        << RobustLossName(loss);
  }
}

TEST(RobustLossWeights, HuberIsCeresHuberLossDerivative) {
  const ceres::HuberLoss huber(kScale);
  for (const double r : kResiduals) {
    double rho[3];
    huber.Evaluate(r * r, rho);
    EXPECT_NEAR(IrlsWeight(RobustLoss::kHuber, r, kScale), rho[1], 1e-15) << r;
  }
}

TEST(RobustLossWeights, NamesRoundTripAndUnknownNamesAreRefused) {
  for (const RobustLoss loss : {RobustLoss::kL2, RobustLoss::kL1, RobustLoss::kHuber, RobustLoss::kGemanMcClure,
                                RobustLoss::kLHalf}) {
    EXPECT_EQ(ParseRobustLoss(RobustLossName(loss)), loss);
    EXPECT_EQ(nlohmann::json(loss).get<RobustLoss>(), loss);
  }
  EXPECT_THROW(ParseRobustLoss("cauchy"), InputError);
  EXPECT_THROW(nlohmann::json("tukey").get<RobustLoss>(), nlohmann::json::type_error);
  EXPECT_THROW(nlohmann::json(3).get<RobustLoss>(), nlohmann::json::type_error);
}

}  // namespace
}  // namespace pgba
