#include "benchmark/perturbed_start.h"

#include <cmath>
#include <limits>
#include <random>

#include "pgba/geometry/rotation.h"

namespace pgba {

std::map<uint32_t, Pose> PerturbedStart(const std::map<uint32_t, Pose>& poses, double deg, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  const double angle = deg * M_PI / 180.0;
  std::map<uint32_t, Pose> out;
  for (const auto& [id, pose] : poses) {
    double baseline = std::numeric_limits<double>::infinity();
    for (const auto& [other, p] : poses)
      if (other != id) baseline = std::min(baseline, (p.C() - pose.C()).norm());
    if (!std::isfinite(baseline)) baseline = 0.0;
    const Eigen::Matrix3d R = pose.R() * RandomRotationOfAngle(rng, angle);
    const Eigen::Vector3d direction = Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized();
    out[id] = Pose::FromRC(R, pose.C() + angle * baseline * direction);
  }
  return out;
}

}  // namespace pgba
