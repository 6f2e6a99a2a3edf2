// Pose conventions (ARCHITECTURE.md): x_cam = R (X - C), COLMAP q = quat(R), t = -R C.
#include "pgba/geometry/pose.h"

#include <gtest/gtest.h>

#include <random>

#include "pgba/geometry/rotation.h"

namespace pgba {
namespace {

Eigen::Vector3d RandomVector(std::mt19937& rng, double scale) {
  std::uniform_real_distribution<double> u(-scale, scale);
  return Eigen::Vector3d(u(rng), u(rng), u(rng));
}

TEST(Pose, DefaultIsIdentity) {
  const Pose p;
  EXPECT_EQ(p.R(), Eigen::Matrix3d::Identity());
  EXPECT_EQ(p.C(), Eigen::Vector3d::Zero());
  EXPECT_EQ(p.ToCamera(Eigen::Vector3d(1, 2, 3)), Eigen::Vector3d(1, 2, 3));
}

TEST(Pose, FromRCAndFromQtAgree) {
  std::mt19937 rng(1);
  for (int trial = 0; trial < 100; ++trial) {
    const Eigen::Matrix3d R = RandomRotation(rng);
    const Eigen::Vector3d C = RandomVector(rng, 100.0);
    const Pose a = Pose::FromRC(R, C);
    EXPECT_LT((a.R() - R).norm(), 1e-14);
    EXPECT_LT((a.C() - C).norm(), 1e-12);
    // COLMAP storage: t = -R C, q the rotation's quaternion.
    EXPECT_LT((a.t() + R * C).norm(), 1e-12);
    EXPECT_NEAR(a.q().norm(), 1.0, 1e-15);
    const Pose b = Pose::FromQt(Eigen::Quaterniond(R), -R * C);
    EXPECT_LT((b.R() - R).norm(), 1e-14);
    EXPECT_LT((b.C() - C).norm(), 1e-12);
    // A non-unit quaternion is normalised (COLMAP files carry rounded quaternions).
    Eigen::Quaterniond q2 = a.q();
    q2.coeffs() *= 1.001;
    const Pose c = Pose::FromQt(q2, a.t());
    EXPECT_NEAR(c.q().norm(), 1.0, 1e-15);
    EXPECT_LT((c.R() - R).norm(), 1e-14);
  }
}

// A quaternion that is already unit length (to rounding) is stored bit for bit, so that
// COLMAP text models read and written back are identical.
TEST(Pose, FromQtKeepsUnitQuaternionBits) {
  std::mt19937 rng(2);
  for (int trial = 0; trial < 1000; ++trial) {
    const Eigen::Quaterniond q = Pose::FromRC(RandomRotation(rng), Eigen::Vector3d::Zero()).q();
    const Pose p = Pose::FromQt(q, Eigen::Vector3d(1, 2, 3));
    EXPECT_EQ(p.q().coeffs(), q.coeffs());
  }
}

TEST(Pose, ToCameraFollowsConvention) {
  std::mt19937 rng(3);
  for (int trial = 0; trial < 100; ++trial) {
    const Eigen::Matrix3d R = RandomRotation(rng);
    const Eigen::Vector3d C = RandomVector(rng, 10.0), X = RandomVector(rng, 10.0);
    const Pose p = Pose::FromRC(R, C);
    EXPECT_LT((p.ToCamera(X) - R * (X - C)).norm(), 1e-12);
    EXPECT_LT(p.ToCamera(C).norm(), 1e-12);  // the centre is the camera origin
    // A point along the viewing direction lies on the optical axis, in front.
    const Eigen::Vector3d on_axis = p.ToCamera(C + 5.0 * p.ViewingDirection());
    EXPECT_LT(on_axis.head<2>().norm(), 1e-12);
    EXPECT_NEAR(on_axis.z(), 5.0, 1e-12);
  }
}

TEST(Pose, RelativePoseComposes) {
  std::mt19937 rng(4);
  for (int trial = 0; trial < 100; ++trial) {
    const Pose a = Pose::FromRC(RandomRotation(rng), RandomVector(rng, 10.0));
    const Pose b = Pose::FromRC(RandomRotation(rng), RandomVector(rng, 10.0));
    const Pose ab = RelativePose(a, b);
    // x_b = R_ab x_a + t_ab for every world point.
    for (int k = 0; k < 5; ++k) {
      const Eigen::Vector3d X = RandomVector(rng, 10.0);
      EXPECT_LT((ab.ToCamera(a.ToCamera(X)) - b.ToCamera(X)).norm(), 1e-11);
    }
    EXPECT_LT((ab.R() - b.R() * a.R().transpose()).norm(), 1e-14);
    // b's centre seen from a.
    EXPECT_LT((ab.C() - a.ToCamera(b.C())).norm(), 1e-11);
    // Identity and inverse.
    const Pose aa = RelativePose(a, a);
    EXPECT_LT((aa.R() - Eigen::Matrix3d::Identity()).norm(), 1e-14);
    EXPECT_LT(aa.t().norm(), 1e-12);
    const Pose ba = RelativePose(b, a);
    EXPECT_LT((ba.R() * ab.R() - Eigen::Matrix3d::Identity()).norm(), 1e-14);
    // Chaining: rel(a, c) = rel(b, c) o rel(a, b).
    const Pose c = Pose::FromRC(RandomRotation(rng), RandomVector(rng, 10.0));
    const Pose ac = RelativePose(a, c), bc = RelativePose(b, c);
    const Eigen::Vector3d x = RandomVector(rng, 5.0);
    EXPECT_LT((ac.ToCamera(x) - bc.ToCamera(ab.ToCamera(x))).norm(), 1e-11);
  }
}

}  // namespace
}  // namespace pgba
