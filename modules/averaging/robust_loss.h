// Robust losses used by the iteratively reweighted least squares (IRLS) solvers of the
// averaging stage. IRLS minimises sum_e rho(|r_e|) by repeatedly solving weighted linear
// least squares with weight w(r) = rho'(r) / r (Chatterjee & Govindu, "Robust Relative
// Rotation Averaging", TPAMI 2017, section 4).
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace pgba {

enum class RobustLoss {
  kL2,            // rho = r^2 / 2: no robustness (weight 1)
  kL1,            // rho = |r|: weight 1 / |r| (Weiszfeld-like IRLS of the L1 problem)
  kHuber,         // quadratic below `scale`, linear above
  kGemanMcClure,  // rho = r^2 / (r^2 + scale^2): redescending, outliers get weight -> 0
  kLHalf,         // rho = |r|^(1/2): Chatterjee & Govindu's preferred loss
};

// IRLS weight w(r) = rho'(r) / r, normalised so that w(0) = 1 for the bounded-weight losses
// (L2, Huber, Geman-McClure). For L1 and l1/2 the weight diverges at 0: |r| is clamped to
// `floor` (1e-3 * scale by default).
double IrlsWeight(RobustLoss loss, double r, double scale);

// Names used in JSON configs: "l2", "l1", "huber", "geman_mcclure", "l_half".
const char* RobustLossName(RobustLoss loss);
// Throws InputError for an unknown name.
RobustLoss ParseRobustLoss(const std::string& name);

void to_json(nlohmann::json& j, const RobustLoss& loss);
// Unknown names throw nlohmann::json::type_error (reported with file and section by the
// config reader).
void from_json(const nlohmann::json& j, RobustLoss& loss);

}  // namespace pgba
