// One robust loss type for every solver of the project. A Ceres problem takes its loss from
// CreateLossFunction(), an IRLS loop (the averaging stage, the global BA's reweighting, the
// local Hessian's h) takes its weight from IrlsWeight() of the same object: a loss is named,
// scaled, validated and serialised once, and the two uses cannot drift apart
// (tests/optim/loss_function_options_test.cc checks IrlsWeight(r) against rho'(r^2) of the
// Ceres loss).
//
// Conventions (Ceres'): the loss rho(s) takes the squared residual norm s = r^2, and the IRLS
// weight of a residual r is rho'(r^2): weighted least squares with that weight has the
// robust problem's stationary points (Chatterjee & Govindu, TPAMI 2017, section 4).
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace ceres {
class LossFunction;
}

namespace pgba {

enum class LossType {
  kTrivial,       // "trivial": plain least squares, rho(s) = s (Ceres' name)
  kL2,            // "l2": the same loss under the averaging stage's name
  kHuber,         // "huber": quadratic up to `scale`, linear beyond
  kCauchy,        // "cauchy": rho(s) = c^2 log(1 + s / c^2), c = scale
  kL1,            // "l1": rho = |r| (weight 1 / |r|), |r| clamped to 1e-3 * scale near 0
  kGemanMcClure,  // "geman_mcclure": redescending, weight (1 + r^2 / c^2)^-2
  kLHalf,         // "l_half": rho = |r|^(1/2) (Chatterjee & Govindu's preferred), clamped as l1
};

struct LossFunctionOptions {
  LossType type = LossType::kTrivial;
  // Where the loss turns robust, in the residual's unit (pixels, degrees, ...): Huber's and
  // Cauchy's scale; the clamp 1e-3 * scale of l1 and l_half.
  double scale = 1.0;

  // The Ceres loss, owned by the caller (or by the ceres::Problem it is handed to with
  // TAKE_OWNERSHIP); nullptr for trivial / l2 (Ceres' plain least squares).
  ceres::LossFunction* CreateLossFunction() const;
  // rho'(r^2) of that loss for residual norm r: 1 at r = 0 for the bounded-weight losses
  // (trivial, l2, huber, cauchy, geman_mcclure); 1 / max(|r|, floor) for l1 and
  // max(|r|, floor)^-1.5 for l_half (the IRLS weights of the averaging stage, unchanged).
  double IrlsWeight(double r) const;
  // Empty when valid, else one line naming the field and its valid range.
  std::string Check() const;
};

// The names configs use: "trivial", "l2", "huber", "cauchy", "l1", "geman_mcclure", "l_half".
const char* LossTypeName(LossType type);
// Throws InputError for an unknown name (the message lists the valid ones).
LossType ParseLossType(const std::string& name);

void to_json(nlohmann::json& j, const LossType& type);
// Unknown names throw nlohmann::json::type_error (reported with file and section by the
// config reader, io/json_config.h).
void from_json(const nlohmann::json& j, LossType& type);
// {"type": "huber", "scale": 1.0}. The options structs that embed a loss keep their own flat
// keys ("loss", "loss_scale_px", ...: util/json_fields.h), so a config names a loss by those keys.
void to_json(nlohmann::json& j, const LossFunctionOptions& loss);
void from_json(const nlohmann::json& j, LossFunctionOptions& loss);

}  // namespace pgba
