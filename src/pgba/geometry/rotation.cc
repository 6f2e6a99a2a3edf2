#include "pgba/geometry/rotation.h"

#include <Eigen/SVD>
#include <cmath>

namespace pgba {

Eigen::Matrix3d Skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d S;
  S << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return S;
}

Eigen::Matrix3d ExpSO3(const Eigen::Vector3d& omega) {
  const double theta2 = omega.squaredNorm();
  const Eigen::Matrix3d W = Skew(omega);
  double a, b;  // R = I + a W + b W^2
  if (theta2 < 1e-12) {
    a = 1.0 - theta2 / 6.0;
    b = 0.5 - theta2 / 24.0;
  } else {
    const double theta = std::sqrt(theta2);
    a = std::sin(theta) / theta;
    b = (1.0 - std::cos(theta)) / theta2;
  }
  return Eigen::Matrix3d::Identity() + a * W + b * W * W;
}

Eigen::Vector3d LogSO3(const Eigen::Matrix3d& R) {
  Eigen::Quaterniond q(R);
  q.normalize();
  if (q.w() < 0) q.coeffs() = -q.coeffs();  // angle in [0, pi]
  const Eigen::Vector3d v = q.vec();
  const double s = v.norm();
  if (s < 1e-12) return 2.0 * v / q.w();  // first order; w ~ 1
  const double theta = 2.0 * std::atan2(s, q.w());
  return theta * v / s;
}

Eigen::Matrix3d RightJacobianSO3(const Eigen::Vector3d& omega) {
  const double theta2 = omega.squaredNorm();
  const Eigen::Matrix3d W = Skew(omega);
  double a, b;  // Jr = I - a W + b W^2
  if (theta2 < 1e-8) {
    a = 0.5 - theta2 / 24.0;
    b = 1.0 / 6.0 - theta2 / 120.0;
  } else {
    const double theta = std::sqrt(theta2);
    a = (1.0 - std::cos(theta)) / theta2;
    b = (theta - std::sin(theta)) / (theta2 * theta);
  }
  return Eigen::Matrix3d::Identity() - a * W + b * W * W;
}

Eigen::Matrix3d InverseRightJacobianSO3(const Eigen::Vector3d& phi) {
  const double theta2 = phi.squaredNorm();
  const Eigen::Matrix3d W = Skew(phi);
  double b;  // Jr^-1 = I + W / 2 + b W^2
  if (theta2 < 1e-8) {
    b = 1.0 / 12.0 + theta2 / 720.0;
  } else {
    const double theta = std::sqrt(theta2);
    b = 1.0 / theta2 - (1.0 + std::cos(theta)) / (2.0 * theta * std::sin(theta));
  }
  return Eigen::Matrix3d::Identity() + 0.5 * W + b * W * W;
}

Eigen::Matrix3d ClosestRotation(const Eigen::Matrix3d& M) {
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  D(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1.0 : 1.0;
  return svd.matrixU() * D * svd.matrixV().transpose();
}

double RotationAngle(const Eigen::Matrix3d& Ra, const Eigen::Matrix3d& Rb) {
  return LogSO3(Ra.transpose() * Rb).norm();
}

double RotationAngleDeg(const Eigen::Matrix3d& Ra, const Eigen::Matrix3d& Rb) {
  return RotationAngle(Ra, Rb) * 180.0 / M_PI;
}

}  // namespace pgba
