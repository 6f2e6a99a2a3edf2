// The one pose parameterisation of every adjustment (ARCHITECTURE.md conventions):
// a 6-vector [C(3), omega(3)] around a reference rotation R0, with
//     R = R0 * Exp(omega),   x_cam = R (X - C).
// The local Hessian (modules/local_hessian) and the pointless global residual
// (modules/global_ba) must use exactly this vector, in this order, or the Hessian weights
// the wrong directions. Point-based BA and the triplet BA use it as well, so that all of
// them share the reprojection cost below.
#pragma once

#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include <Eigen/Core>

#include "pgba/geometry/pose.h"
#include "pgba/geometry/rotation.h"
#include "pgba/scene/camera.h"

namespace pgba {

// Parameter block of one pose: C then omega.
using PoseVector = Eigen::Matrix<double, 6, 1>;

// A pose being optimised: the reference rotation R0 and the increment block (initially 0
// for omega, the centre for C).
struct PoseBlock {
  Eigen::Matrix3d R0 = Eigen::Matrix3d::Identity();
  PoseVector x = PoseVector::Zero();

  static PoseBlock FromPose(const Pose& pose) {
    PoseBlock b;
    b.R0 = pose.R();
    b.x.head<3>() = pose.C();
    return b;
  }
  Pose ToPose() const { return Pose::FromRC(R0 * ExpSO3(x.tail<3>()), x.head<3>()); }
  // Folds omega into R0 (re-linearisation between solves) so omega stays small.
  void Relinearize() {
    R0 = ClosestRotation(R0 * ExpSO3(x.tail<3>()));
    x.tail<3>().setZero();
  }
};

// Fixes the 7-dof similarity gauge of an adjustment through two of its poses: `a` held
// constant, and the centre coordinate of `b` along their largest baseline component (the
// scale). The problem must own its manifolds (the default).
inline void HoldPoseAndScale(PoseBlock* a, PoseBlock* b, ceres::Problem* problem) {
  problem->SetParameterBlockConstant(a->x.data());
  int coord = 0;
  (b->x.head<3>() - a->x.head<3>()).cwiseAbs().maxCoeff(&coord);
  problem->SetManifold(b->x.data(), new ceres::SubsetManifold(6, {coord}));
}

// x_cam = R0 * Exp(omega) * (X - C) for any scalar type (Ceres Jets included).
template <typename T>
void WorldToCamera(const Eigen::Matrix3d& R0, const T* pose, const T* X, T* x_cam) {
  const T d[3] = {X[0] - pose[0], X[1] - pose[1], X[2] - pose[2]};
  T y[3];
  ceres::AngleAxisRotatePoint(pose + 3, d, y);  // Exp(omega) * d
  for (int r = 0; r < 3; ++r) x_cam[r] = T(R0(r, 0)) * y[0] + T(R0(r, 1)) * y[1] + T(R0(r, 2)) * y[2];
}

// Pixel reprojection residual of one observation: blocks (pose[6], point[3]). The optional
// `weight` scales the residual (the local BA's attenuation sqrt(gamma/M)).
struct ReprojectionError {
  ReprojectionError(const Camera* camera, const Eigen::Matrix3d& R0, const Eigen::Vector2d& pixel,
                    double weight = 1.0)
      : camera(camera), R0(R0), pixel(pixel), weight(weight) {}

  template <typename T>
  bool operator()(const T* pose, const T* X, T* residual) const {
    T xc[3];
    WorldToCamera(R0, pose, X, xc);
    // A point behind the camera projects to a finite but meaningless pixel; the robust
    // loss and the outlier filters of the callers deal with it.
    T px[2];
    ProjectToPixel(camera->model, camera->params.data(), xc, px);
    residual[0] = T(weight) * (px[0] - T(pixel.x()));
    residual[1] = T(weight) * (px[1] - T(pixel.y()));
    return true;
  }

  static ceres::CostFunction* Create(const Camera* camera, const Eigen::Matrix3d& R0, const Eigen::Vector2d& pixel,
                                     double weight = 1.0) {
    return new ceres::AutoDiffCostFunction<ReprojectionError, 2, 6, 3>(
        new ReprojectionError(camera, R0, pixel, weight));
  }

  const Camera* camera;
  Eigen::Matrix3d R0;
  Eigen::Vector2d pixel;
  double weight;
};

}  // namespace pgba
