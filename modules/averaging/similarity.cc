#include "averaging/similarity.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "pgba/geometry/rotation.h"

namespace pgba {

Eigen::Matrix3d AverageTripletRotation(const Triplet& triplet, const std::map<uint32_t, Eigen::Matrix3d>& rotations) {
  Eigen::Matrix3d sum = Eigen::Matrix3d::Zero();
  for (int k = 0; k < 3; ++k) sum += triplet.local_poses[k].R().transpose() * rotations.at(triplet.image_ids[k]);
  return ClosestRotation(sum);
}

TripletSimilarityFit EstimateTripletSimilarity(const Triplet& triplet, const std::map<uint32_t, Pose>& poses) {
  TripletSimilarityFit fit;
  std::map<uint32_t, Eigen::Matrix3d> rotations;
  Eigen::Vector3d C[3], c[3];
  for (int k = 0; k < 3; ++k) {
    const Pose& P = poses.at(triplet.image_ids[k]);
    rotations[triplet.image_ids[k]] = P.R();
    C[k] = P.C();
    c[k] = triplet.local_poses[k].C();
  }
  const Eigen::Matrix3d alpha = AverageTripletRotation(triplet, rotations);
  const Eigen::Vector3d C_bar = (C[0] + C[1] + C[2]) / 3.0;
  const Eigen::Vector3d c_bar = (c[0] + c[1] + c[2]) / 3.0;
  double num = 0.0, den = 0.0, local_spread = 0.0;
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d G = alpha * (C[k] - C_bar);
    num += (c[k] - c_bar).dot(G);
    den += G.squaredNorm();
    local_spread += (c[k] - c_bar).squaredNorm();
  }
  const double lambda = num / den;
  if (!(den > 0.0) || !(lambda > 0.0) || !std::isfinite(lambda)) return fit;

  fit.global_to_local.s = lambda;
  fit.global_to_local.R = alpha;
  fit.global_to_local.t = c_bar - lambda * (alpha * C_bar);
  double misfit = 0.0;
  for (int k = 0; k < 3; ++k) {
    misfit += (c[k] - fit.global_to_local.Apply(C[k])).squaredNorm();
    const Eigen::Matrix3d r_pred = rotations[triplet.image_ids[k]] * alpha.transpose();
    fit.rotation_residual_deg =
        std::max(fit.rotation_residual_deg, RotationAngleDeg(triplet.local_poses[k].R(), r_pred));
  }
  fit.centre_residual_rel = local_spread > 0.0 ? std::sqrt(misfit / local_spread) : 0.0;
  fit.valid = true;
  return fit;
}

std::vector<TripletSimilarityFit> ComputeTripletSimilarities(const std::map<uint32_t, Pose>& poses,
                                                             std::vector<Triplet>* triplets) {
  std::vector<TripletSimilarityFit> fits(triplets->size());
  tbb::parallel_for(size_t(0), triplets->size(), [&](size_t t) {
    fits[t] = EstimateTripletSimilarity((*triplets)[t], poses);
    if (fits[t].valid) (*triplets)[t].global_to_local = fits[t].global_to_local;
  });
  return fits;
}

}  // namespace pgba
