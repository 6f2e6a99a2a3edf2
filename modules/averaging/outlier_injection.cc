#include "averaging/outlier_injection.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

#include "pgba/io/option_ranges.h"
#include "pgba/geometry/rotation.h"
#include "pgba/util/error.h"

namespace pgba {
namespace {

// round(fraction * n) distinct indices in [0, n), ascending (partial Fisher-Yates).
std::vector<int> Choose(size_t n, double fraction, std::mt19937_64& rng) {
  const size_t k = std::min(n, static_cast<size_t>(std::llround(fraction * static_cast<double>(n))));
  std::vector<int> all(n);
  std::iota(all.begin(), all.end(), 0);
  for (size_t i = 0; i < k; ++i) {
    std::uniform_int_distribution<size_t> pick(i, n - 1);
    std::swap(all[i], all[pick(rng)]);
  }
  all.resize(k);
  std::sort(all.begin(), all.end());
  return all;
}

}  // namespace

void to_json(nlohmann::json& j, const OutlierTarget& target) {
  j = target == OutlierTarget::kPairs ? "pairs" : target == OutlierTarget::kTriplets ? "triplets" : "both";
}

void from_json(const nlohmann::json& j, OutlierTarget& target) {
  const std::string s = j.is_string() ? j.get<std::string>() : j.dump();
  if (s == "pairs")
    target = OutlierTarget::kPairs;
  else if (s == "triplets")
    target = OutlierTarget::kTriplets;
  else if (s == "both")
    target = OutlierTarget::kBoth;
  else
    throw nlohmann::json::type_error::create(
        302, "unknown outlier target '" + s + "' (expected pairs, triplets or both)", &j);
}

void to_json(nlohmann::json& j, const TripletCorruption& mode) {
  j = mode == TripletCorruption::kLocalPoses ? "local_poses" : "relative_rotations";
}

void from_json(const nlohmann::json& j, TripletCorruption& mode) {
  const std::string s = j.is_string() ? j.get<std::string>() : j.dump();
  if (s == "relative_rotations")
    mode = TripletCorruption::kRelativeRotations;
  else if (s == "local_poses")
    mode = TripletCorruption::kLocalPoses;
  else
    throw nlohmann::json::type_error::create(
        302, "unknown triplet corruption '" + s + "' (expected relative_rotations or local_poses)", &j);
}

OutlierInjectionResult InjectRotationOutliers(const OutlierInjectionOptions& options,
                                              std::vector<TwoViewGeometry>* pairs, std::vector<LocalMotion>* triplets) {
  if (!(options.fraction >= 0.0 && options.fraction <= 1.0))
    throw InputError("outlier fraction must be in [0, 1], got " + std::to_string(options.fraction));
  OutlierInjectionResult result;
  std::mt19937_64 rng(options.seed);
  if (options.target != OutlierTarget::kTriplets && pairs) {
    result.pairs = Choose(pairs->size(), options.fraction, rng);
    for (int p : result.pairs) (*pairs)[p].R_21 = RandomRotation(rng);
  }
  if (options.target != OutlierTarget::kPairs && triplets) {
    result.triplets = Choose(triplets->size(), options.fraction, rng);
    for (int t : result.triplets) {
      std::uniform_int_distribution<int> view(0, 2);
      Pose& pose = (*triplets)[t].local_poses[view(rng)];
      pose = Pose::FromRC(RandomRotation(rng), pose.C());
    }
  }
  return result;
}

CorruptedRelativeMotions CorruptRelativeMotions(const OutlierInjectionOptions& options,
                                                const std::vector<TwoViewGeometry>& pairs,
                                                const std::vector<LocalMotion>& triplets) {
  CorruptedRelativeMotions out{pairs, triplets, triplets, {}};
  const bool local = options.triplet_corruption == TripletCorruption::kLocalPoses;
  out.injected = InjectRotationOutliers(options, &out.pairs, local ? &out.triplets : &out.rotation_measurements);
  if (local) out.rotation_measurements = out.triplets;
  return out;
}

std::string OutlierInjectionOptions::Check() const {
  if (const std::string m = CheckRanges(*this, "OutlierInjectionOptions"); !m.empty()) return m;
  return "";
}

}  // namespace pgba
