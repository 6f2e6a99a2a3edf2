// Outlier injection for the paper's sensitivity experiment (section 4, "we randomly infuse
// the relative rotations with outliers"): a given fraction of the relative rotations, of the
// pairs and/or of the triplets, is replaced by uniformly random rotations before averaging.
//
// What is corrupted. A pair is a measurement only: its R_21 is replaced. A triplet is both a
// measurement (its three relative rotations r_b r_a^T enter rotation averaging and the pair
// validation) and a piece of local geometry (its local poses, used by translation averaging,
// the similarities and the global BA, with a local BA fitted to its points behind them). Two
// experiments, chosen by `triplet_corruption`:
//   - relative_rotations (default; `pgba init --rotation-outliers`): the relative rotations
//     the triplet contributes to the averaging are corrupted, its local poses stay what its
//     local BA estimated. This is the sensitivity test of the initialisation: the averaging
//     must find the right rotations and name the outlier measurements, and no image may be
//     lost for them;
//   - local_poses: the triplet itself is corrupted (a local pose gets a random rotation), so
//     that the global BA faces outlier triplets (the benchmark's sweep, with the triplet
//     filtering of global_init.h disabled). With the filtering on, such triplets are dropped,
//     and an image whose every triplet is corrupted has nothing left to register it with.
// In both, one random view of the triplet gets a random rotation, which corrupts two of its
// three relative rotations and leaves them cycle-consistent with each other (a triplet's own
// cycle cannot reveal it).
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "pgba/scene/view_graph.h"

namespace pgba {

enum class OutlierTarget { kPairs, kTriplets, kBoth };
enum class TripletCorruption { kRelativeRotations, kLocalPoses };

struct OutlierInjectionOptions {
  // Fraction in [0, 1] of the targeted relative motions to corrupt (0 disables).
  double fraction = 0.0;
  // "pairs": R_21 of a pair; "triplets": the rotation of one (random) view of a triplet's
  // local poses, its centre kept, which corrupts two of the triplet's three relative
  // rotations; "both": the fraction of each, independently.
  OutlierTarget target = OutlierTarget::kBoth;
  // "relative_rotations" or "local_poses" (see above). InjectRotationOutliers itself always
  // corrupts the triplets it is given; CorruptRelativeMotions corrupts a copy that serves as
  // the rotation measurements only in the relative_rotations case.
  TripletCorruption triplet_corruption = TripletCorruption::kRelativeRotations;
  uint64_t seed = 1;
  // Empty when valid, else one line naming the first field out of its valid range (the
  // ranges of io/option_ranges.cc) or breaking a rule between fields.
  std::string Check() const;
};
void to_json(nlohmann::json& j, const OutlierTarget& target);
void from_json(const nlohmann::json& j, OutlierTarget& target);  // json type_error if unknown
void to_json(nlohmann::json& j, const TripletCorruption& mode);
void from_json(const nlohmann::json& j, TripletCorruption& mode);  // json type_error if unknown
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(OutlierInjectionOptions, fraction, target, triplet_corruption, seed)

struct OutlierInjectionResult {
  std::vector<int> pairs;     // indices of the corrupted pairs (ascending)
  std::vector<int> triplets;  // indices of the corrupted triplets (ascending)
};

// Corrupts exactly round(fraction * count) randomly chosen pairs and/or triplets in place,
// deterministically for a given seed. Throws InputError if fraction is outside [0, 1].
OutlierInjectionResult InjectRotationOutliers(const OutlierInjectionOptions& options,
                                              std::vector<TwoViewGeometry>* pairs, std::vector<LocalMotion>* triplets);

// The experiment's input to RunGlobalInitialisation (global_init.h): the pairs with their
// corrupted R_21, the triplets (their local poses corrupted only with kLocalPoses) and the
// triplets as the rotation averaging measures them (corrupted in both experiments).
struct CorruptedRelativeMotions {
  std::vector<TwoViewGeometry> pairs;
  std::vector<LocalMotion> triplets;
  std::vector<LocalMotion> rotation_measurements;  // aligned with triplets
  OutlierInjectionResult injected;
};
CorruptedRelativeMotions CorruptRelativeMotions(const OutlierInjectionOptions& options,
                                                const std::vector<TwoViewGeometry>& pairs,
                                                const std::vector<LocalMotion>& triplets);

}  // namespace pgba
