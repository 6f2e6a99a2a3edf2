#include "averaging/robust_loss.h"

#include <algorithm>
#include <cmath>

#include "pgba/util/error.h"

namespace pgba {

double IrlsWeight(RobustLoss loss, double r, double scale) {
  const double a = std::abs(r);
  switch (loss) {
    case RobustLoss::kL2:
      return 1.0;
    case RobustLoss::kL1:
      return 1.0 / std::max(a, 1e-3 * scale);
    case RobustLoss::kHuber:
      return a <= scale ? 1.0 : scale / a;
    case RobustLoss::kGemanMcClure: {
      // rho = r^2 / (r^2 + s^2), rho'(r) / r = 2 s^2 / (r^2 + s^2)^2; normalised by w(0).
      const double d = 1.0 + (a * a) / (scale * scale);
      return 1.0 / (d * d);
    }
    case RobustLoss::kLHalf:
      // rho = |r|^(1/2): rho'(r) / r = 1/2 |r|^(-3/2).
      return std::pow(std::max(a, 1e-3 * scale), -1.5);
  }
  return 1.0;
}

const char* RobustLossName(RobustLoss loss) {
  switch (loss) {
    case RobustLoss::kL2:
      return "l2";
    case RobustLoss::kL1:
      return "l1";
    case RobustLoss::kHuber:
      return "huber";
    case RobustLoss::kGemanMcClure:
      return "geman_mcclure";
    case RobustLoss::kLHalf:
      return "l_half";
  }
  return "?";
}

RobustLoss ParseRobustLoss(const std::string& name) {
  for (RobustLoss l : {RobustLoss::kL2, RobustLoss::kL1, RobustLoss::kHuber, RobustLoss::kGemanMcClure,
                       RobustLoss::kLHalf})
    if (name == RobustLossName(l)) return l;
  throw InputError("unknown robust loss '" + name + "' (expected l2, l1, huber, geman_mcclure or l_half)");
}

void to_json(nlohmann::json& j, const RobustLoss& loss) { j = RobustLossName(loss); }

// A JSON exception (not InputError): the config reader (io/json_config.h) turns it into an
// InputError naming the file and the section.
void from_json(const nlohmann::json& j, RobustLoss& loss) {
  try {
    if (!j.is_string()) throw InputError("robust loss must be a string, got " + j.dump());
    loss = ParseRobustLoss(j.get<std::string>());
  } catch (const InputError& e) {
    throw nlohmann::json::type_error::create(302, e.what(), &j);
  }
}

}  // namespace pgba
