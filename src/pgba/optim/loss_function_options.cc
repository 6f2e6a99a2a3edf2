#include "pgba/optim/loss_function_options.h"

#include <ceres/loss_function.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "pgba/util/error.h"

namespace pgba {
namespace {

constexpr LossType kAllTypes[] = {LossType::kTrivial, LossType::kL2,           LossType::kHuber, LossType::kCauchy,
                                  LossType::kL1,      LossType::kGemanMcClure, LossType::kLHalf};

// The clamp of |r| near 0 for l1 and l_half, whose weights diverge there.
double Floor(double scale) { return 1e-3 * scale; }

// rho(s) = s b / (s + b), b = c^2: rho'(s) = (1 + s / b)^-2, the Geman-McClure IRLS weight.
class GemanMcClureLoss : public ceres::LossFunction {
 public:
  explicit GemanMcClureLoss(double c) : b_(c * c) {}
  void Evaluate(double s, double rho[3]) const override {
    const double d = s + b_;
    rho[0] = s * b_ / d;
    rho[1] = (b_ / d) * (b_ / d);
    rho[2] = -2.0 * rho[1] / d;
  }

 private:
  const double b_;
};

// rho(s) = 4 s^(1/4) - 3 f^(1/2) above f^2 (rho'(s) = s^(-3/4) = |r|^(-3/2)), linear below
// (rho' = f^(-3/2)): l_half with its weight clamped at |r| = f, continuous at f^2.
class LHalfLoss : public ceres::LossFunction {
 public:
  explicit LHalfLoss(double floor) : f_(floor) {}
  void Evaluate(double s, double rho[3]) const override {
    if (s <= f_ * f_) {
      rho[1] = std::pow(f_, -1.5);
      rho[0] = s * rho[1];
      rho[2] = 0.0;
      return;
    }
    rho[0] = 4.0 * std::pow(s, 0.25) - 3.0 * std::sqrt(f_);
    rho[1] = std::pow(s, -0.75);
    rho[2] = -0.75 * rho[1] / s;
  }

 private:
  const double f_;
};

}  // namespace

ceres::LossFunction* LossFunctionOptions::CreateLossFunction() const {
  switch (type) {
    case LossType::kTrivial:
    case LossType::kL2:
      return nullptr;
    case LossType::kHuber:
      return new ceres::HuberLoss(scale);
    case LossType::kCauchy:
      return new ceres::CauchyLoss(scale);
    case LossType::kL1:
      // Huber at the floor f divided by f: rho'(s) = 1 / max(|r|, f).
      return new ceres::ScaledLoss(new ceres::HuberLoss(Floor(scale)), 1.0 / Floor(scale), ceres::TAKE_OWNERSHIP);
    case LossType::kGemanMcClure:
      return new GemanMcClureLoss(scale);
    case LossType::kLHalf:
      return new LHalfLoss(Floor(scale));
  }
  return nullptr;
}

// The formulas the IRLS loops used before this type existed, unchanged to the last bit
// (Cauchy: the global BA's motion reweighting; the others: the averaging stage).
double LossFunctionOptions::IrlsWeight(double r) const {
  const double a = std::abs(r);
  switch (type) {
    case LossType::kTrivial:
    case LossType::kL2:
      return 1.0;
    case LossType::kHuber:
      return a <= scale ? 1.0 : scale / a;
    case LossType::kCauchy: {
      const double u = r / scale;
      return 1.0 / (1.0 + u * u);
    }
    case LossType::kL1:
      return 1.0 / std::max(a, Floor(scale));
    case LossType::kGemanMcClure: {
      const double d = 1.0 + (a * a) / (scale * scale);
      return 1.0 / (d * d);
    }
    case LossType::kLHalf:
      return std::pow(std::max(a, Floor(scale)), -1.5);
  }
  return 1.0;
}

std::string LossFunctionOptions::Check() const {
  if (!(scale > 0) || !std::isfinite(scale)) {
    char buf[64];
    std::snprintf(buf, sizeof(buf), "scale = %.17g is out of range (> 0)", scale);
    return buf;
  }
  return "";
}

const char* LossTypeName(LossType type) {
  switch (type) {
    case LossType::kTrivial:
      return "trivial";
    case LossType::kL2:
      return "l2";
    case LossType::kHuber:
      return "huber";
    case LossType::kCauchy:
      return "cauchy";
    case LossType::kL1:
      return "l1";
    case LossType::kGemanMcClure:
      return "geman_mcclure";
    case LossType::kLHalf:
      return "l_half";
  }
  return "?";
}

LossType ParseLossType(const std::string& name) {
  for (const LossType t : kAllTypes)
    if (name == LossTypeName(t)) return t;
  std::string list;
  for (const LossType t : kAllTypes) list += std::string(list.empty() ? "" : ", ") + LossTypeName(t);
  throw InputError("unknown robust loss '" + name + "' (expected one of: " + list + ")");
}

void to_json(nlohmann::json& j, const LossType& type) { j = LossTypeName(type); }

// A JSON exception (not InputError): the config reader turns it into an InputError naming
// the file and the section.
void from_json(const nlohmann::json& j, LossType& type) {
  try {
    if (!j.is_string()) throw InputError("robust loss must be a string, got " + j.dump());
    type = ParseLossType(j.get<std::string>());
  } catch (const InputError& e) {
    throw nlohmann::json::type_error::create(302, e.what(), &j);
  }
}

void to_json(nlohmann::json& j, const LossFunctionOptions& loss) { j = {{"type", loss.type}, {"scale", loss.scale}}; }

void from_json(const nlohmann::json& j, LossFunctionOptions& loss) {
  const LossFunctionOptions defaults;
  loss.type = j.value("type", defaults.type);
  loss.scale = j.value("scale", defaults.scale);
}

}  // namespace pgba
