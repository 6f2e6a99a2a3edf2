#include "modules/global_ba/motion_similarity.h"

#include <cmath>

#include "pgba/geometry/rotation.h"

namespace pgba {

Eigen::Matrix3d MotionSimilarity::alpha() const { return alpha0 * ExpSO3(x.segment<3>(3)); }

Sim3 MotionSimilarity::ToSim3() const {
  Sim3 s;
  s.s = lambda();
  s.R = alpha();
  s.t = beta() - s.s * (s.R * G);
  return s;
}

void MotionSimilarity::Relinearize() {
  alpha0 = ClosestRotation(alpha());
  x.segment<3>(3).setZero();
}

MotionSimilarity InitializeSimilarity(const std::vector<Pose>& global_poses, const std::vector<Pose>& local_poses,
                                       const Sim3& fallback) {
  const MotionSimilarityFit fit = FitMotionSimilarity(global_poses, local_poses);
  MotionSimilarity sim;
  sim.G = fit.global_centroid;
  sim.alpha0 = fit.alpha;
  sim.x.head<3>() = fit.local_centroid;
  sim.x(6) = fit.scale_ok() ? fit.lambda : (fallback.s > 0 ? fallback.s : 1.0);
  return sim;
}

MotionSimilarity SimilarityFromSim3(const std::vector<Pose>& global_poses, const Sim3& global_to_local) {
  MotionSimilarity sim;
  sim.G = MeanCentre(global_poses);
  sim.alpha0 = global_to_local.R;
  sim.x.head<3>() = global_to_local.Apply(sim.G);
  sim.x(6) = global_to_local.s;
  return sim;
}

}  // namespace pgba
