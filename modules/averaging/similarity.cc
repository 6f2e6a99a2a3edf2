#include "averaging/similarity.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "pgba/geometry/rotation.h"

namespace pgba {

Eigen::Matrix3d AverageTripletRotation(const LocalMotion& triplet, const std::map<uint32_t, Eigen::Matrix3d>& rotations) {
  std::vector<Eigen::Matrix3d> global_R, local_R;
  for (int k = 0; k < 3; ++k) {
    global_R.push_back(rotations.at(triplet.image_ids[k]));
    local_R.push_back(triplet.local_poses[k].R());
  }
  return MotionRotation(global_R, local_R);
}

TripletSimilarityFit EstimateTripletSimilarity(const LocalMotion& triplet, const std::map<uint32_t, Pose>& poses) {
  TripletSimilarityFit fit;
  std::vector<Pose> global(3), local(triplet.local_poses.begin(), triplet.local_poses.end());
  for (int k = 0; k < 3; ++k) global[k] = poses.at(triplet.image_ids[k]);
  const MotionSimilarityFit eq4 = FitMotionSimilarity(global, local);
  if (!eq4.scale_ok()) return fit;
  fit.global_to_local = eq4.ToSim3();
  double misfit = 0.0, local_spread = 0.0;
  for (int k = 0; k < 3; ++k) {
    misfit += (local[k].C() - fit.global_to_local.Apply(global[k].C())).squaredNorm();
    local_spread += (local[k].C() - eq4.local_centroid).squaredNorm();
    const Eigen::Matrix3d r_pred = global[k].R() * eq4.alpha.transpose();
    fit.rotation_residual_deg = std::max(fit.rotation_residual_deg, RotationAngleDeg(local[k].R(), r_pred));
  }
  fit.centre_residual_rel = local_spread > 0.0 ? std::sqrt(misfit / local_spread) : 0.0;
  fit.valid = true;
  return fit;
}

std::vector<TripletSimilarityFit> ComputeTripletSimilarities(const std::map<uint32_t, Pose>& poses,
                                                             std::vector<LocalMotion>* triplets) {
  std::vector<TripletSimilarityFit> fits(triplets->size());
  tbb::parallel_for(size_t(0), triplets->size(), [&](size_t t) {
    fits[t] = EstimateTripletSimilarity((*triplets)[t], poses);
    if (fits[t].valid) (*triplets)[t].global_to_local = fits[t].global_to_local;
  });
  return fits;
}

}  // namespace pgba
