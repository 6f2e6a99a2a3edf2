#include "averaging/relative_rotations.h"

#include "pgba/io/option_ranges.h"
#include "averaging/connectivity.h"

namespace pgba {

std::vector<RelativeRotation> CollectRelativeRotations(const std::vector<TwoViewGeometry>& pairs,
                                                       const std::vector<LocalMotion>& triplets,
                                                       const RelativeRotationOptions& options) {
  std::vector<RelativeRotation> out;
  if (options.use_pairs) {
    for (size_t k = 0; k < pairs.size(); ++k) {
      const TwoViewGeometry& p = pairs[k];
      if (p.image_id1 == p.image_id2) continue;
      RelativeRotation r;
      r.image_id1 = p.image_id1;
      r.image_id2 = p.image_id2;
      r.R_21 = p.R_21;
      r.weight = options.pair_weight;
      r.support = p.num_inliers;
      r.source = static_cast<int>(k);
      out.push_back(r);
    }
  }
  if (options.use_triplets) {
    for (size_t k = 0; k < triplets.size(); ++k) {
      const LocalMotion& t = triplets[k];
      if (!HasDistinctImages(t)) continue;
      for (int a = 0; a < 3; ++a)
        for (int b = a + 1; b < 3; ++b) {
          RelativeRotation r;
          r.image_id1 = t.image_ids[a];
          r.image_id2 = t.image_ids[b];
          r.R_21 = t.local_poses[b].R() * t.local_poses[a].R().transpose();
          r.weight = options.triplet_weight * 2.0 / 3.0;
          r.support = static_cast<double>(t.track_ids.size());
          r.source = static_cast<int>(pairs.size() + k);
          out.push_back(r);
        }
    }
  }
  return out;
}

std::string RelativeRotationOptions::Check() const {
  if (const std::string m = CheckRanges(*this, "global_init.rotation.observations"); !m.empty()) return m;
  return "";
}

}  // namespace pgba
