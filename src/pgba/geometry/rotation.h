// SO(3) tools used everywhere: hat operator, exponential and logarithm maps, projection
// of a 3x3 matrix to the closest rotation, angular distances, COLMAP quaternion order.
//
// Convention (ARCHITECTURE.md): rotation increments are right-multiplied,
// R = R0 * Exp(omega), omega in radians.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace pgba {

// [v]_x such that [v]_x w = v x w.
Eigen::Matrix3d Skew(const Eigen::Vector3d& v);

// Rodrigues' formula, exact to machine precision also for |omega| -> 0 (Taylor branch).
Eigen::Matrix3d ExpSO3(const Eigen::Vector3d& omega);

// Inverse of ExpSO3 for angles in [0, pi]. Uses the atan2 form through the unit
// quaternion, so that angles of 1e-9 rad are still resolved (the acos form loses them,
// and the local Hessian's rotation eigenvalues of ~1e9 / px^2 would amplify the error).
Eigen::Vector3d LogSO3(const Eigen::Matrix3d& R);

// Right Jacobian of SO(3): Exp(omega + d) = Exp(omega) Exp(Jr(omega) d) to first order in d,
// and its inverse: Log(R Exp(u)) = Log(R) + Jr^-1(Log(R)) u. Series branches near 0 keep both
// exact to machine precision there (the linearisation point of every solve).
Eigen::Matrix3d RightJacobianSO3(const Eigen::Vector3d& omega);
Eigen::Matrix3d InverseRightJacobianSO3(const Eigen::Vector3d& phi);

// argmin_{R in SO(3)} ||R - M||_F via SVD (det forced to +1).
Eigen::Matrix3d ClosestRotation(const Eigen::Matrix3d& M);

// Geodesic distance angle(Ra^T Rb) in radians / degrees.
double RotationAngle(const Eigen::Matrix3d& Ra, const Eigen::Matrix3d& Rb);
double RotationAngleDeg(const Eigen::Matrix3d& Ra, const Eigen::Matrix3d& Rb);

// Uniformly random rotation from a standard normal quaternion draw, or a rotation of
// exactly `angle` radians about a random axis. `Rng` is any std random engine.
template <typename Rng>
Eigen::Matrix3d RandomRotation(Rng& rng);
template <typename Rng>
Eigen::Matrix3d RandomRotationOfAngle(Rng& rng, double angle);

}  // namespace pgba

#include <random>

namespace pgba {
template <typename Rng>
Eigen::Matrix3d RandomRotation(Rng& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::Quaterniond q(n(rng), n(rng), n(rng), n(rng));
  q.normalize();
  return q.toRotationMatrix();
}
template <typename Rng>
Eigen::Matrix3d RandomRotationOfAngle(Rng& rng, double angle) {
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::Vector3d axis(n(rng), n(rng), n(rng));
  axis.normalize();
  return ExpSO3(angle * axis);
}
}  // namespace pgba
