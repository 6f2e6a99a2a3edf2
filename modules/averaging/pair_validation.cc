#include "averaging/pair_validation.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "pgba/io/option_ranges.h"
#include "pgba/geometry/rotation.h"
#include "pgba/util/upper_median.h"

namespace pgba {
namespace {

struct Disagreement {
  std::vector<double> rotation_deg, direction_deg;
};

double AngleDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b)) * 180.0 / M_PI;
}

// Angle between R_21 R_1 and R_2; 0 (no evidence against the pair) if an image has no
// rotation.
double ResidualUnderRotationsDeg(const TwoViewGeometry& p, const std::map<uint32_t, Eigen::Matrix3d>& rotations) {
  auto r1 = rotations.find(p.image_id1), r2 = rotations.find(p.image_id2);
  if (r1 == rotations.end() || r2 == rotations.end()) return 0.0;
  return RotationAngleDeg(p.R_21 * r1->second, r2->second);
}

}  // namespace

std::vector<TwoViewGeometry> PairsConsistentWithTriplets(const std::vector<TwoViewGeometry>& pairs,
                                                         const std::vector<LocalMotion>& triplets,
                                                         const PairValidationOptions& options,
                                                         const std::map<uint32_t, Eigen::Matrix3d>* rotations,
                                                         int* num_rejected) {
  if (num_rejected) *num_rejected = 0;
  if (!options.enabled) return pairs;
  // The triplets' relative motions, keyed by the ordered image pair (id1 < id2) they imply.
  std::map<std::pair<uint32_t, uint32_t>, std::vector<std::pair<Eigen::Matrix3d, Eigen::Vector3d>>> implied;
  for (const LocalMotion& t : triplets)
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) {
        if (a == b || t.image_ids[a] >= t.image_ids[b]) continue;
        const Pose& p1 = t.local_poses[a];
        const Pose& p2 = t.local_poses[b];
        // x_2 = R_21 x_1 + t_21: R_21 = r_2 r_1^T, t_21 ~ r_2 (c_1 - c_2).
        implied[{t.image_ids[a], t.image_ids[b]}].push_back(
            {p2.R() * p1.R().transpose(), (p2.R() * (p1.C() - p2.C())).normalized()});
      }
  std::vector<TwoViewGeometry> kept;
  for (const TwoViewGeometry& p : pairs) {
    const bool forward = p.image_id1 < p.image_id2;
    auto it = implied.find(std::minmax(p.image_id1, p.image_id2));
    if (it == implied.end()) {
      if (!rotations || ResidualUnderRotationsDeg(p, *rotations) <= options.max_rotation_deg) {
        kept.push_back(p);
      } else if (num_rejected) {
        ++*num_rejected;
      }
      continue;
    }
    // The pair's motion in the orientation of the key (id1 < id2).
    const Eigen::Matrix3d R = forward ? p.R_21 : Eigen::Matrix3d(p.R_21.transpose());
    const Eigen::Vector3d t = (forward ? p.t_21 : Eigen::Vector3d(-(p.R_21.transpose() * p.t_21))).normalized();
    Disagreement d;
    for (const auto& [R_t, t_t] : it->second) {
      d.rotation_deg.push_back(RotationAngleDeg(R, R_t));
      d.direction_deg.push_back(AngleDeg(t, t_t));
    }
    if (UpperMedian(d.rotation_deg) <= options.max_rotation_deg &&
        UpperMedian(d.direction_deg) <= options.max_direction_deg) {
      kept.push_back(p);
    } else if (num_rejected) {
      ++*num_rejected;
    }
  }
  return kept;
}

std::string PairValidationOptions::Check() const {
  if (const std::string m = CheckRanges(*this, "global_init.pair_validation"); !m.empty()) return m;
  return "";
}

}  // namespace pgba
