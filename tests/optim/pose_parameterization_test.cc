// The one pose parameterisation [C, omega], R = R0 Exp(omega), checked numerically
// (ARCHITECTURE.md: "A unit test checks this numerically"): WorldToCamera agrees with Pose,
// the reprojection cost's Jacobian w.r.t. the 6-vector matches finite differences of an
// independent evaluation through PoseBlock::ToPose, and re-linearisation keeps the pose.
#include "pgba/optim/pose_parameterization.h"

#include <gtest/gtest.h>

#include <memory>
#include <random>

namespace pgba {
namespace {

Eigen::Vector3d RandomVector(std::mt19937& rng, double scale) {
  std::uniform_real_distribution<double> u(-scale, scale);
  return Eigen::Vector3d(u(rng), u(rng), u(rng));
}

Camera MakeCamera() {
  Camera c;
  c.model = CameraModel::kOpenCV;
  c.width = 1920;
  c.height = 1080;
  c.params = {1000, 1012, 955.5, 547.25, -0.15, 0.04, 0.002, -0.001};
  return c;
}

// Pixel of X under the pose a PoseBlock with vector x describes, computed only through
// Pose and Camera (independent of WorldToCamera / ReprojectionError).
Eigen::Vector2d PixelThroughPose(const Camera& cam, const Eigen::Matrix3d& R0, const PoseVector& x,
                                 const Eigen::Vector3d& X) {
  PoseBlock b;
  b.R0 = R0;
  b.x = x;
  return cam.Project(b.ToPose().ToCamera(X));
}

TEST(PoseParameterization, WorldToCameraMatchesPose) {
  std::mt19937 rng(1);
  for (int trial = 0; trial < 100; ++trial) {
    const Pose pose = Pose::FromRC(RandomRotation(rng), RandomVector(rng, 10.0));
    PoseBlock b = PoseBlock::FromPose(pose);
    EXPECT_EQ(b.x.tail<3>(), Eigen::Vector3d::Zero());
    const Eigen::Vector3d X = RandomVector(rng, 10.0);
    Eigen::Vector3d xc;
    WorldToCamera(b.R0, b.x.data(), X.data(), xc.data());
    EXPECT_LT((xc - pose.ToCamera(X)).norm(), 1e-12 * (1 + xc.norm()));
    // With a rotation increment: right-multiplied, R = R0 Exp(omega) (not Exp(omega) R0).
    b.x.tail<3>() = RandomVector(rng, 0.3);
    WorldToCamera(b.R0, b.x.data(), X.data(), xc.data());
    const Eigen::Vector3d expected = b.R0 * ExpSO3(b.x.tail<3>()) * (X - b.x.head<3>());
    EXPECT_LT((xc - expected).norm(), 1e-12 * (1 + xc.norm()));
    EXPECT_LT((xc - b.ToPose().ToCamera(X)).norm(), 1e-12 * (1 + xc.norm()));
    const Eigen::Vector3d left = ExpSO3(b.x.tail<3>()) * b.R0 * (X - b.x.head<3>());
    EXPECT_GT((xc - left).norm(), 1e-3);
  }
}

// Residual value and Jacobians of the Ceres cost against central differences of the
// independent pixel evaluation, at omega = 0 (where every solver linearises) and away
// from it.
TEST(PoseParameterization, ReprojectionJacobianMatchesFiniteDifferences) {
  std::mt19937 rng(2);
  const Camera cam = MakeCamera();
  int tested = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::Matrix3d R0 = RandomRotation(rng);
    PoseVector x;
    x.head<3>() = RandomVector(rng, 5.0);
    x.tail<3>() = trial % 2 ? RandomVector(rng, 0.2) : Eigen::Vector3d::Zero();
    // A point in front of the camera, inside the image.
    const Eigen::Matrix3d R = R0 * ExpSO3(x.tail<3>());
    const Eigen::Vector3d xc = (3.0 + trial % 7) * Eigen::Vector3d(RandomVector(rng, 0.8).head<2>().homogeneous());
    const Eigen::Vector3d X = R.transpose() * xc + x.head<3>();
    const Eigen::Vector2d pixel = PixelThroughPose(cam, R0, x, X) + Eigen::Vector2d(1.5, -2.0);
    const double weight = 0.7;
    std::unique_ptr<ceres::CostFunction> cost(ReprojectionError::Create(&cam, R0, pixel, weight));
    ASSERT_EQ(cost->num_residuals(), 2);
    ASSERT_EQ(cost->parameter_block_sizes(), std::vector<int32_t>({6, 3}));
    const double* params[2] = {x.data(), X.data()};
    Eigen::Vector2d r;
    Eigen::Matrix<double, 2, 6, Eigen::RowMajor> J_pose;
    Eigen::Matrix<double, 2, 3, Eigen::RowMajor> J_point;
    double* jacobians[2] = {J_pose.data(), J_point.data()};
    ASSERT_TRUE(cost->Evaluate(params, r.data(), jacobians));
    EXPECT_LT((r - weight * (PixelThroughPose(cam, R0, x, X) - pixel)).norm(), 1e-9);
    const double h = 1e-6;
    for (int k = 0; k < 6; ++k) {
      PoseVector xp = x, xm = x;
      xp(k) += h;
      xm(k) -= h;
      const Eigen::Vector2d fd =
          weight * (PixelThroughPose(cam, R0, xp, X) - PixelThroughPose(cam, R0, xm, X)) / (2 * h);
      EXPECT_LT((J_pose.col(k) - fd).norm(), 1e-5 * (1 + fd.norm())) << "pose dof " << k;
    }
    for (int k = 0; k < 3; ++k) {
      Eigen::Vector3d Xp = X, Xm = X;
      Xp(k) += h;
      Xm(k) -= h;
      const Eigen::Vector2d fd =
          weight * (PixelThroughPose(cam, R0, x, Xp) - PixelThroughPose(cam, R0, x, Xm)) / (2 * h);
      EXPECT_LT((J_point.col(k) - fd).norm(), 1e-5 * (1 + fd.norm())) << "point dof " << k;
    }
    // Gauge: moving the centre and the point together leaves the residual unchanged.
    EXPECT_LT((J_pose.leftCols<3>() + J_point).norm(), 1e-8 * (1 + J_point.norm()));
    ++tested;
  }
  EXPECT_EQ(tested, 200);
}

TEST(PoseParameterization, PoseBlockRoundTripAndRelinearize) {
  std::mt19937 rng(3);
  for (int trial = 0; trial < 100; ++trial) {
    const Pose pose = Pose::FromRC(RandomRotation(rng), RandomVector(rng, 10.0));
    PoseBlock b = PoseBlock::FromPose(pose);
    const Pose back = b.ToPose();
    EXPECT_LT(RotationAngle(back.R(), pose.R()), 1e-14);
    EXPECT_LT((back.C() - pose.C()).norm(), 1e-13);
    // An update, then re-linearisation: same pose, omega folded into R0.
    b.x += (PoseVector() << RandomVector(rng, 1.0), RandomVector(rng, 0.5)).finished();
    const Pose before = b.ToPose();
    const PoseVector x_before = b.x;
    b.Relinearize();
    EXPECT_EQ(b.x.tail<3>(), Eigen::Vector3d::Zero());
    EXPECT_EQ(b.x.head<3>(), x_before.head<3>());
    EXPECT_LT((b.R0.transpose() * b.R0 - Eigen::Matrix3d::Identity()).norm(), 1e-15 * 10);
    EXPECT_NEAR(b.R0.determinant(), 1.0, 1e-15 * 10);
    const Pose after = b.ToPose();
    EXPECT_LT(RotationAngle(after.R(), before.R()), 1e-14);
    EXPECT_LT((after.C() - before.C()).norm(), 1e-14 * (1 + before.C().norm()));
    const Eigen::Vector3d X = RandomVector(rng, 10.0);
    EXPECT_LT((after.ToCamera(X) - before.ToCamera(X)).norm(), 1e-12);
  }
}

}  // namespace
}  // namespace pgba
