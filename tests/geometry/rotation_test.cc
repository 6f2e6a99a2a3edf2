// SO(3) tools against analytic truth: Exp/Log inverse over the whole angle range (tiny angles
// and near pi included), Log accuracy against the analytic small-angle value, closest
// rotation, angular distances.
#include "pgba/geometry/rotation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace pgba {
namespace {

Eigen::Vector3d RandomUnit(std::mt19937& rng) {
  std::normal_distribution<double> n;
  return Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized();
}

bool IsRotation(const Eigen::Matrix3d& R, double tol) {
  return (R.transpose() * R - Eigen::Matrix3d::Identity()).norm() < tol && std::abs(R.determinant() - 1.0) < tol;
}

TEST(Rotation, SkewIsCrossProduct) {
  std::mt19937 rng(1);
  for (int i = 0; i < 20; ++i) {
    const Eigen::Vector3d v = 3.0 * RandomUnit(rng), w = 2.0 * RandomUnit(rng);
    EXPECT_LT((Skew(v) * w - v.cross(w)).norm(), 1e-14);
    EXPECT_EQ((Skew(v) + Skew(v).transpose()).norm(), 0.0);
  }
}

TEST(Rotation, ExpMatchesAngleAxis) {
  std::mt19937 rng(2);
  for (double angle : {1e-12, 1e-7, 1e-3, 0.5, 2.0, 3.1}) {
    const Eigen::Vector3d axis = RandomUnit(rng);
    const Eigen::Matrix3d expected = Eigen::AngleAxisd(angle, axis).toRotationMatrix();
    const Eigen::Matrix3d R = ExpSO3(angle * axis);
    EXPECT_LT((R - expected).norm(), 1e-15 * 10) << angle;
    EXPECT_TRUE(IsRotation(R, 1e-14)) << angle;
  }
  EXPECT_EQ(ExpSO3(Eigen::Vector3d::Zero()), Eigen::Matrix3d::Identity());
}

// Log(Exp(w)) = w for |w| in [0, pi), with relative accuracy; tiny angles included.
TEST(Rotation, LogInvertsExpOverAllAngles) {
  std::mt19937 rng(3);
  const double angles[] = {1e-14, 1e-10, 1e-9, 1e-8, 1e-6, 1e-4, 1e-2, 0.1, 1.0, 2.0, 3.0, M_PI - 1e-3, M_PI - 1e-6};
  for (double angle : angles) {
    for (int trial = 0; trial < 20; ++trial) {
      const Eigen::Vector3d w = angle * RandomUnit(rng);
      const Eigen::Vector3d back = LogSO3(ExpSO3(w));
      // Near pi the axis is recovered from the symmetric part, so the error is relative to
      // the distance from pi: sqrt(eps)-level there, eps-level elsewhere.
      const double tol = angle > 3.1 ? 1e-7 : 1e-13;
      EXPECT_LT((back - w).norm(), tol * std::max(angle, 1e-300) + 1e-300)
          << "angle " << angle << " w " << w.transpose() << " back " << back.transpose();
    }
  }
}

// Exp(Log(R)) = R for random rotations, including exactly pi (axis sign is free there).
TEST(Rotation, ExpInvertsLog) {
  std::mt19937 rng(4);
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::Matrix3d R = RandomRotation(rng);
    const Eigen::Vector3d w = LogSO3(R);
    EXPECT_LE(w.norm(), M_PI + 1e-12);
    EXPECT_LT((ExpSO3(w) - R).norm(), 1e-14);
  }
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::Vector3d axis = RandomUnit(rng);
    const Eigen::Matrix3d R = Eigen::AngleAxisd(M_PI, axis).toRotationMatrix();
    const Eigen::Vector3d w = LogSO3(R);
    EXPECT_NEAR(w.norm(), M_PI, 1e-7);
    EXPECT_NEAR(std::abs(w.normalized().dot(axis)), 1.0, 1e-12);
    EXPECT_LT((ExpSO3(w) - R).norm(), 1e-7);
  }
}

// The small-angle accuracy the local Hessian needs (ARCHITECTURE.md: eigenvalues ~1e9/px^2
// make a 1e-8 rad error in Log visible): an analytic rotation about a coordinate axis by
// angle a has R(2,1) = sin a; Log must return a to relative 1e-12 even for a = 1e-10,
// where the acos form returns 0 (1 - cos a underflows the trace).
TEST(Rotation, LogSmallAngleMatchesAnalytic) {
  for (double a : {1e-12, 1e-10, 3e-9, 1e-8, 1e-7, 1e-5, 1e-3}) {
    Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
    R(1, 1) = R(2, 2) = std::cos(a);
    R(2, 1) = std::sin(a);
    R(1, 2) = -std::sin(a);
    const Eigen::Vector3d w = LogSO3(R);
    EXPECT_NEAR(w.x(), a, 1e-12 * a) << a;
    EXPECT_EQ(w.y(), 0.0);
    EXPECT_EQ(w.z(), 0.0);
    // Geodesic distance of two nearby rotations.
    std::mt19937 rng(5);
    const Eigen::Matrix3d R0 = RandomRotation(rng);
    EXPECT_NEAR(RotationAngle(R0, R0 * R), a, 1e-9 * a + 1e-15) << a;
  }
  // The acos form would give exactly 0 here: make sure we are not using it.
  const double a = 1e-9;
  const Eigen::Matrix3d R = ExpSO3(Eigen::Vector3d(0, 0, a));
  EXPECT_EQ(std::acos(std::min(1.0, 0.5 * (R.trace() - 1.0))), 0.0);
  EXPECT_NEAR(LogSO3(R).z(), a, 1e-12 * a);
}

TEST(Rotation, ClosestRotationOfPerturbedRotation) {
  std::mt19937 rng(6);
  std::normal_distribution<double> n(0.0, 1e-3);
  for (int trial = 0; trial < 50; ++trial) {
    const Eigen::Matrix3d R = RandomRotation(rng);
    // Exact rotations are fixed points.
    EXPECT_LT((ClosestRotation(R) - R).norm(), 1e-14);
    // A scaled rotation projects back to the rotation.
    EXPECT_LT((ClosestRotation(2.5 * R) - R).norm(), 1e-14);
    Eigen::Matrix3d E;
    for (int k = 0; k < 9; ++k) E(k) = n(rng);
    const Eigen::Matrix3d M = R + E;
    const Eigen::Matrix3d P = ClosestRotation(M);
    EXPECT_TRUE(IsRotation(P, 1e-13));
    // First order: only the skew part of R^T E survives the projection.
    const Eigen::Matrix3d A = R.transpose() * E;
    const Eigen::Matrix3d expected = R * (Eigen::Matrix3d::Identity() + 0.5 * (A - A.transpose()));
    EXPECT_LT((P - expected).norm(), 1e-5);
    // It is the closest: no nearby rotation is closer in Frobenius norm.
    for (int k = 0; k < 10; ++k) {
      const Eigen::Matrix3d Q = P * ExpSO3(1e-3 * RandomUnit(rng));
      EXPECT_LE((P - M).norm(), (Q - M).norm());
    }
  }
}

TEST(Rotation, ClosestRotationOfReflectionHasPositiveDeterminant) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 50; ++trial) {
    const Eigen::Matrix3d R = RandomRotation(rng);
    const Eigen::Matrix3d reflect = Eigen::Vector3d(1, 1, -1).asDiagonal();
    const Eigen::Matrix3d M = R * reflect;  // det = -1
    ASSERT_LT(M.determinant(), 0);
    const Eigen::Matrix3d P = ClosestRotation(M);
    EXPECT_TRUE(IsRotation(P, 1e-13));
    EXPECT_NEAR(P.determinant(), 1.0, 1e-13);
  }
  // A rank-deficient matrix still gives a proper rotation.
  const Eigen::Matrix3d P = ClosestRotation(Eigen::Vector3d(1, 2, 0).asDiagonal());
  EXPECT_TRUE(IsRotation(P, 1e-13));
  EXPECT_LT((P - Eigen::Matrix3d::Identity()).norm(), 1e-14);
}

TEST(Rotation, RotationAngleDeg) {
  std::mt19937 rng(8);
  for (double deg : {0.0, 1e-6, 0.01, 1.0, 45.0, 90.0, 135.0, 179.0}) {
    const Eigen::Matrix3d Ra = RandomRotation(rng);
    const Eigen::Matrix3d Rb = Ra * RandomRotationOfAngle(rng, deg * M_PI / 180.0);
    EXPECT_NEAR(RotationAngleDeg(Ra, Rb), deg, 1e-10 + 1e-12 * deg) << deg;
    EXPECT_NEAR(RotationAngleDeg(Rb, Ra), deg, 1e-10 + 1e-12 * deg) << deg;
    // Left-multiplied difference has the same angle (conjugation invariance).
    const Eigen::Matrix3d Rc = RandomRotationOfAngle(rng, deg * M_PI / 180.0) * Ra;
    EXPECT_NEAR(RotationAngleDeg(Ra, Rc), deg, 1e-10 + 1e-12 * deg) << deg;
  }
  EXPECT_NEAR(RotationAngleDeg(Eigen::Matrix3d::Identity(), Eigen::Vector3d(-1, -1, 1).asDiagonal()), 180.0, 1e-9);
}

TEST(Rotation, RandomRotationIsUniformish) {
  // A uniform rotation's angle has density (1 - cos t) / pi on [0, pi]: mean pi/2 + 2/pi.
  std::mt19937 rng(9);
  double sum = 0;
  const int n = 20000;
  for (int i = 0; i < n; ++i) {
    const Eigen::Matrix3d R = RandomRotation(rng);
    ASSERT_TRUE(IsRotation(R, 1e-13));
    sum += LogSO3(R).norm();
  }
  EXPECT_NEAR(sum / n, M_PI / 2 + 2 / M_PI, 0.02);
}

}  // namespace
}  // namespace pgba
