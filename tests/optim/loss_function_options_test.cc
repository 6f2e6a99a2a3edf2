// The one loss type (optim/loss_function_options.h): its IRLS weight against each loss's
// definition and against the Ceres loss it creates, its names and JSON, its Check().
//
// Against the definition: w(r) = rho'(r) / r, with rho'(r) taken by central differences of
// rho written here, at residuals on both sides of the scale (and both signs). Bounded-weight
// losses (L2, Huber, Cauchy, Geman-McClure) are normalised to w(0) = 1, so
// w(r) = (rho'(r) / r) / lim_0 rho'/r; L1 and l1/2 diverge at 0, so only ratios w(r) / w(r_ref)
// are defined by the loss (any constant factor cancels in the weighted least squares), and
// |r| is clamped at 1e-3 scale.
// Against Ceres: the loss CreateLossFunction() hands to a Ceres problem has rho'(s = r^2) =
// IrlsWeight(r), and its rho' and rho'' are the derivatives of its rho (central differences).
#include "pgba/optim/loss_function_options.h"

#include <ceres/loss_function.h>
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <memory>

#include "pgba/util/error.h"

namespace pgba {
namespace {

constexpr double kScale = 0.7;
constexpr LossType kAll[] = {LossType::kTrivial, LossType::kL2,           LossType::kHuber, LossType::kCauchy,
                             LossType::kL1,      LossType::kGemanMcClure, LossType::kLHalf};

std::function<double(double)> Rho(LossType type) {
  const double s = kScale;
  switch (type) {
    case LossType::kTrivial:
    case LossType::kL2:
      return [](double r) { return 0.5 * r * r; };
    case LossType::kL1:
      return [](double r) { return std::abs(r); };
    case LossType::kHuber:
      return [s](double r) { return std::abs(r) <= s ? 0.5 * r * r : s * std::abs(r) - 0.5 * s * s; };
    case LossType::kCauchy:
      return [s](double r) { return 0.5 * s * s * std::log1p(r * r / (s * s)); };
    case LossType::kGemanMcClure:
      return [s](double r) { return r * r / (r * r + s * s); };
    case LossType::kLHalf:
      return [](double r) { return std::sqrt(std::abs(r)); };
  }
  return nullptr;
}

// rho'(r) / r by central differences.
double WeightByDefinition(LossType type, double r) {
  const auto rho = Rho(type);
  const double h = 1e-6 * std::max(std::abs(r), 1e-3);
  return (rho(r + h) - rho(r - h)) / (2 * h) / r;
}

double Weight(LossType type, double r) { return LossFunctionOptions{type, kScale}.IrlsWeight(r); }

const std::vector<double> kResiduals = {-5.3, -0.9, -0.2, 0.05, 0.3, 0.69, 0.71, 1.4, 3.0, 12.0};

TEST(LossFunctionOptions, BoundedLossesAreRhoPrimeOverRNormalisedAtZero) {
  for (const LossType type :
       {LossType::kTrivial, LossType::kL2, LossType::kHuber, LossType::kCauchy, LossType::kGemanMcClure}) {
    const double w0 = WeightByDefinition(type, 1e-4);  // lim_{r -> 0} rho'(r) / r
    EXPECT_NEAR(Weight(type, 0.0), 1.0, 1e-12) << LossTypeName(type);
    for (const double r : kResiduals)
      EXPECT_NEAR(Weight(type, r), WeightByDefinition(type, r) / w0, 1e-6) << LossTypeName(type) << " r " << r;
  }
}

TEST(LossFunctionOptions, UnboundedLossesHaveTheRatiosOfRhoPrimeOverR) {
  for (const LossType type : {LossType::kL1, LossType::kLHalf}) {
    const double ref = 1.0;
    for (const double r : kResiduals) {
      const double expected = WeightByDefinition(type, r) / WeightByDefinition(type, ref);
      EXPECT_NEAR(Weight(type, r) / Weight(type, ref) / expected, 1.0, 1e-6) << LossTypeName(type) << " r " << r;
    }
    // Below the floor 1e-3 scale the weight stops growing: that of |r| = 1e-3 scale.
    const double floor = 1e-3 * kScale;
    EXPECT_DOUBLE_EQ(Weight(type, 1e-9), Weight(type, floor)) << LossTypeName(type);
    EXPECT_DOUBLE_EQ(Weight(type, 0.0), Weight(type, floor)) << LossTypeName(type);
    EXPECT_NEAR(Weight(type, floor) / Weight(type, ref),
                WeightByDefinition(type, floor) / WeightByDefinition(type, ref), 1e-6 * Weight(type, floor))
        << LossTypeName(type);
  }
}

TEST(LossFunctionOptions, CeresLossHasTheIrlsWeightAsRhoPrime) {
  for (const LossType type : kAll) {
    const LossFunctionOptions options{type, kScale};
    const std::unique_ptr<ceres::LossFunction> loss(options.CreateLossFunction());
    const bool plain = type == LossType::kTrivial || type == LossType::kL2;
    EXPECT_EQ(loss == nullptr, plain) << LossTypeName(type);  // nullptr: Ceres' plain least squares
    if (!loss) continue;
    // Residuals on both sides of the scale and of the l1 / l_half floor (7e-4).
    for (const double r : {1e-4, 5e-4, 2e-3, 0.05, 0.3, 0.69, 0.71, 1.4, 3.0, 12.0}) {
      const double s = r * r;
      double rho[3], plus[3], minus[3];
      loss->Evaluate(s, rho);
      EXPECT_NEAR(rho[1], options.IrlsWeight(r), 1e-12 * options.IrlsWeight(r)) << LossTypeName(type) << " r " << r;
      EXPECT_NEAR(options.IrlsWeight(-r), options.IrlsWeight(r), 0.0);
      // rho' and rho'' are the derivatives of rho (away from the kinks at the scale and floor,
      // and from s ~ 0, where Ceres' Cauchy rho = b log(1 + s / b) has lost its digits).
      if (r < 0.01) continue;
      const double h = 1e-5 * s;
      loss->Evaluate(s + h, plus);
      loss->Evaluate(s - h, minus);
      EXPECT_NEAR((plus[0] - minus[0]) / (2 * h), rho[1], 1e-6 * rho[1]) << LossTypeName(type) << " r " << r;
      EXPECT_NEAR((plus[1] - minus[1]) / (2 * h), rho[2], 1e-5 * std::abs(rho[1] / s) + 1e-12)
          << LossTypeName(type) << " r " << r;
      EXPECT_LE(rho[2], 0.0) << LossTypeName(type);  // robust: the weight never grows with r
    }
  }
}

TEST(LossFunctionOptions, NamesAndJsonRoundTripAndUnknownNamesAreRefused) {
  for (const LossType type : kAll) {
    EXPECT_EQ(ParseLossType(LossTypeName(type)), type);
    EXPECT_EQ(nlohmann::json(type).get<LossType>(), type);
    const LossFunctionOptions options{type, 2.5};
    const nlohmann::json j = options;
    EXPECT_EQ(j, nlohmann::json({{"type", LossTypeName(type)}, {"scale", 2.5}}));
    const LossFunctionOptions back = j.get<LossFunctionOptions>();
    EXPECT_EQ(back.type, type);
    EXPECT_EQ(back.scale, 2.5);
  }
  EXPECT_THROW(ParseLossType("tukey"), InputError);
  EXPECT_THROW(nlohmann::json("tukey").get<LossType>(), nlohmann::json::type_error);
  EXPECT_THROW(nlohmann::json(3).get<LossType>(), nlohmann::json::type_error);
}

TEST(LossFunctionOptions, CheckRefusesAScaleThatIsNotPositive) {
  EXPECT_EQ(LossFunctionOptions{}.Check(), "");
  EXPECT_EQ((LossFunctionOptions{LossType::kHuber, 1e-9}.Check()), "");
  for (const double bad : {0.0, -1.0, std::nan(""), HUGE_VAL}) {
    const std::string m = LossFunctionOptions{LossType::kHuber, bad}.Check();
    EXPECT_NE(m.find("scale"), std::string::npos) << bad;
    EXPECT_NE(m.find("> 0"), std::string::npos) << bad;
  }
}

}  // namespace
}  // namespace pgba
