// Camera pose, one convention everywhere (ARCHITECTURE.md):
//   x_cam = R (X - C),  R world->camera rotation, C camera centre in the world.
// Stored as COLMAP stores it (unit quaternion q = quat(R), t = -R C) so that a model read
// from text and written back is bit-identical; R() and C() give the paper's quantities.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace pgba {

class Pose {
 public:
  Pose() : q_(Eigen::Quaterniond::Identity()), t_(Eigen::Vector3d::Zero()) {}

  static Pose FromRC(const Eigen::Matrix3d& R, const Eigen::Vector3d& C);
  // q is normalised (a quaternion already unit to rounding, |q|^2 - 1 <= 1e-14, is kept bit
  // for bit so that text models round-trip exactly).
  static Pose FromQt(const Eigen::Quaterniond& q, const Eigen::Vector3d& t);

  Eigen::Matrix3d R() const { return q_.toRotationMatrix(); }
  Eigen::Vector3d C() const { return -(q_.conjugate() * t_); }
  const Eigen::Quaterniond& q() const { return q_; }
  const Eigen::Vector3d& t() const { return t_; }

  // World point -> camera frame.
  Eigen::Vector3d ToCamera(const Eigen::Vector3d& X) const { return q_ * X + t_; }
  // Viewing direction (camera z axis) in the world.
  Eigen::Vector3d ViewingDirection() const { return q_.conjugate() * Eigen::Vector3d::UnitZ(); }

 private:
  Eigen::Quaterniond q_;
  Eigen::Vector3d t_;
};

// Relative pose of b with respect to a: x_b = R_ab x_a + t_ab, i.e. the pose of b expressed
// in camera a's frame is Pose::FromQt(quat(R_ab), t_ab).
Pose RelativePose(const Pose& a, const Pose& b);

}  // namespace pgba
