// 3D similarity Y = s R X + t, and its estimation from point correspondences (Umeyama,
// through Eigen::umeyama).
//
// Applied to a camera pose (ARCHITECTURE.md, paper eq. 4): a similarity d mapping the
// global frame to a local one sends centre C to c = s R C + t and rotation R_cam to
// R_cam R^T (the camera sees the same directions).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "pgba/geometry/pose.h"

namespace pgba {

struct Sim3 {
  double s = 1.0;
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();

  Eigen::Vector3d Apply(const Eigen::Vector3d& X) const { return s * (R * X) + t; }
  Pose Apply(const Pose& pose) const;
  Sim3 Inverse() const;
  // (a * b)(X) = a(b(X)).
  Sim3 operator*(const Sim3& b) const;
  Eigen::Matrix4d Matrix() const;
};

// Least-squares similarity with dst ~ Apply(src) (Umeyama 1991). Returns false for fewer than
// 3 correspondences or (nearly) collinear / coincident source points.
bool EstimateSim3(const std::vector<Eigen::Vector3d>& src, const std::vector<Eigen::Vector3d>& dst,
                  Sim3* sim);

}  // namespace pgba
