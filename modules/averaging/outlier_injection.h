// Outlier injection for the paper's sensitivity experiment (section 4, "we randomly infuse
// the relative rotations with outliers"): a given fraction of the relative rotations, of the
// pairs and/or of the triplets, is replaced by uniformly random rotations before averaging.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "pgba/scene/view_graph.h"

namespace pgba {

enum class OutlierTarget { kPairs, kTriplets, kBoth };

struct OutlierInjectionOptions {
  // Fraction in [0, 1] of the targeted relative motions to corrupt (0 disables).
  double fraction = 0.0;
  // "pairs": R_21 of a pair; "triplets": the rotation of one (random) view of a triplet's
  // local poses, its centre kept, which corrupts two of the triplet's three relative
  // rotations; "both": the fraction of each, independently.
  OutlierTarget target = OutlierTarget::kBoth;
  uint64_t seed = 1;
};
void to_json(nlohmann::json& j, const OutlierTarget& target);
void from_json(const nlohmann::json& j, OutlierTarget& target);  // json type_error if unknown
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(OutlierInjectionOptions, fraction, target, seed)

struct OutlierInjectionResult {
  std::vector<int> pairs;     // indices of the corrupted pairs (ascending)
  std::vector<int> triplets;  // indices of the corrupted triplets (ascending)
};

// Corrupts exactly round(fraction * count) randomly chosen pairs and/or triplets in place,
// deterministically for a given seed. Throws InputError if fraction is outside [0, 1].
OutlierInjectionResult InjectRotationOutliers(const OutlierInjectionOptions& options,
                                              std::vector<TwoViewGeometry>* pairs, std::vector<Triplet>* triplets);

}  // namespace pgba
