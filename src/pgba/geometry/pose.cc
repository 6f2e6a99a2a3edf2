#include "pgba/geometry/pose.h"

#include <cmath>

namespace pgba {

Pose Pose::FromRC(const Eigen::Matrix3d& R, const Eigen::Vector3d& C) {
  Pose p;
  p.q_ = Eigen::Quaterniond(R).normalized();
  p.t_ = -(p.q_ * C);
  return p;
}

Pose Pose::FromQt(const Eigen::Quaterniond& q, const Eigen::Vector3d& t) {
  Pose p;
  // Normalising is not idempotent in floating point: re-normalising a quaternion that is
  // already unit to rounding changes its last bits, and a COLMAP model read and written
  // back would differ. Such a quaternion is kept as is (its rotation matrix is orthonormal
  // to ~1e-15); anything further from unit length is normalised.
  p.q_ = std::abs(q.squaredNorm() - 1.0) <= 1e-14 ? q : q.normalized();
  p.t_ = t;
  return p;
}

Pose RelativePose(const Pose& a, const Pose& b) {
  // x_b = q_b X + t_b with X = q_a^-1 (x_a - t_a).
  const Eigen::Quaterniond q_ab = b.q() * a.q().conjugate();
  return Pose::FromQt(q_ab, b.t() - q_ab * a.t());
}

}  // namespace pgba
