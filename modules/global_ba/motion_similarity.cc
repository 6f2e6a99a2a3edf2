#include "modules/global_ba/motion_similarity.h"

#include <cmath>

#include "pgba/geometry/rotation.h"

namespace pgba {

namespace {
Eigen::Vector3d Centroid(const std::vector<Pose>& poses) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const Pose& p : poses) sum += p.C();
  return poses.empty() ? sum : Eigen::Vector3d(sum / static_cast<double>(poses.size()));
}
}  // namespace

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
  MotionSimilarity sim;
  sim.G = Centroid(global_poses);
  Eigen::Matrix3d sum = Eigen::Matrix3d::Zero();
  for (size_t k = 0; k < global_poses.size(); ++k) sum += local_poses[k].R().transpose() * global_poses[k].R();
  sim.alpha0 = ClosestRotation(sum);
  const Eigen::Vector3d g = Centroid(local_poses);
  double num = 0.0, den = 0.0;
  for (size_t k = 0; k < global_poses.size(); ++k) {
    const Eigen::Vector3d d = sim.alpha0 * (global_poses[k].C() - sim.G);
    num += (local_poses[k].C() - g).dot(d);
    den += d.squaredNorm();
  }
  const double lambda = den > 0 ? num / den : 0.0;
  sim.x.head<3>() = g;
  sim.x(6) = lambda > 0 && std::isfinite(lambda) ? lambda : (fallback.s > 0 ? fallback.s : 1.0);
  return sim;
}

MotionSimilarity SimilarityFromSim3(const std::vector<Pose>& global_poses, const Sim3& global_to_local) {
  MotionSimilarity sim;
  sim.G = Centroid(global_poses);
  sim.alpha0 = global_to_local.R;
  sim.x.head<3>() = global_to_local.Apply(sim.G);
  sim.x(6) = global_to_local.s;
  return sim;
}

}  // namespace pgba
