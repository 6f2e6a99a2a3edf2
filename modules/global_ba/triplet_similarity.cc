#include "modules/global_ba/triplet_similarity.h"

#include <cmath>

#include "pgba/geometry/rotation.h"

namespace pgba {

namespace {
Eigen::Vector3d Centroid(const std::array<Pose, 3>& poses) {
  return (poses[0].C() + poses[1].C() + poses[2].C()) / 3.0;
}
}  // namespace

Eigen::Matrix3d TripletSimilarity::alpha() const { return alpha0 * ExpSO3(x.segment<3>(3)); }

Sim3 TripletSimilarity::ToSim3() const {
  Sim3 s;
  s.s = lambda();
  s.R = alpha();
  s.t = beta() - s.s * (s.R * G);
  return s;
}

void TripletSimilarity::Relinearize() {
  alpha0 = ClosestRotation(alpha());
  x.segment<3>(3).setZero();
}

TripletSimilarity InitializeSimilarity(const std::array<Pose, 3>& global_poses, const std::array<Pose, 3>& local_poses,
                                       const Sim3& fallback) {
  TripletSimilarity sim;
  sim.G = Centroid(global_poses);
  Eigen::Matrix3d sum = Eigen::Matrix3d::Zero();
  for (int k = 0; k < 3; ++k) sum += local_poses[k].R().transpose() * global_poses[k].R();
  sim.alpha0 = ClosestRotation(sum);
  const Eigen::Vector3d g = Centroid(local_poses);
  double num = 0.0, den = 0.0;
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d d = sim.alpha0 * (global_poses[k].C() - sim.G);
    num += (local_poses[k].C() - g).dot(d);
    den += d.squaredNorm();
  }
  const double lambda = den > 0 ? num / den : 0.0;
  sim.x.head<3>() = g;
  sim.x(6) = lambda > 0 && std::isfinite(lambda) ? lambda : (fallback.s > 0 ? fallback.s : 1.0);
  return sim;
}

TripletSimilarity SimilarityFromSim3(const std::array<Pose, 3>& global_poses, const Sim3& global_to_local) {
  TripletSimilarity sim;
  sim.G = Centroid(global_poses);
  sim.alpha0 = global_to_local.R;
  sim.x.head<3>() = global_to_local.Apply(sim.G);
  sim.x(6) = global_to_local.s;
  return sim;
}

}  // namespace pgba
