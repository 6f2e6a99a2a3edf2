// Sim(3): algebra, Umeyama estimation against a known similarity, and the action on poses
// (paper eq. 4 in the ARCHITECTURE.md convention).
#include "pgba/geometry/sim3.h"

#include <gtest/gtest.h>

#include <random>

#include "pgba/geometry/rotation.h"

namespace pgba {
namespace {

Eigen::Vector3d RandomVector(std::mt19937& rng, double scale) {
  std::uniform_real_distribution<double> u(-scale, scale);
  return Eigen::Vector3d(u(rng), u(rng), u(rng));
}

Sim3 RandomSim3(std::mt19937& rng) {
  std::uniform_real_distribution<double> log_s(-3.0, 3.0);
  Sim3 S;
  S.s = std::exp(log_s(rng));
  S.R = RandomRotation(rng);
  S.t = RandomVector(rng, 50.0);
  return S;
}

TEST(Sim3, ApplyInverseCompose) {
  std::mt19937 rng(1);
  for (int trial = 0; trial < 100; ++trial) {
    const Sim3 a = RandomSim3(rng), b = RandomSim3(rng);
    const Eigen::Vector3d X = RandomVector(rng, 10.0);
    const Eigen::Vector3d Y = a.Apply(X);
    EXPECT_LT((Y - (a.s * a.R * X + a.t)).norm(), 1e-10 * (1 + Y.norm()));
    EXPECT_LT((a.Inverse().Apply(Y) - X).norm(), 1e-10 * (1 + X.norm()));
    EXPECT_LT(((a * b).Apply(X) - a.Apply(b.Apply(X))).norm(), 1e-9 * (1 + a.Apply(b.Apply(X)).norm()));
    const Sim3 id = a * a.Inverse();
    EXPECT_NEAR(id.s, 1.0, 1e-14);
    EXPECT_LT((id.R - Eigen::Matrix3d::Identity()).norm(), 1e-14);
    EXPECT_LT(id.t.norm(), 1e-10 * (1 + a.t.norm()));
    // Matrix form acts the same way on homogeneous points.
    const Eigen::Vector4d Yh = a.Matrix() * X.homogeneous();
    EXPECT_LT((Yh.head<3>() - Y).norm(), 1e-10 * (1 + Y.norm()));
    EXPECT_EQ(Yh(3), 1.0);
  }
}

std::vector<Eigen::Vector3d> RandomCloud(std::mt19937& rng, int n, double scale) {
  std::vector<Eigen::Vector3d> pts(n);
  for (auto& p : pts) p = RandomVector(rng, scale);
  return pts;
}

TEST(Sim3, EstimateRecoversKnownSimilarityExactly) {
  std::mt19937 rng(2);
  for (int trial = 0; trial < 100; ++trial) {
    const Sim3 truth = RandomSim3(rng);
    const int n = 3 + trial % 20;
    const std::vector<Eigen::Vector3d> src = RandomCloud(rng, n, 10.0);
    std::vector<Eigen::Vector3d> dst;
    for (const auto& X : src) dst.push_back(truth.Apply(X));
    Sim3 est;
    ASSERT_TRUE(EstimateSim3(src, dst, &est));
    EXPECT_NEAR(est.s / truth.s, 1.0, 1e-12);
    EXPECT_LT(RotationAngle(est.R, truth.R), 1e-12);
    EXPECT_NEAR(est.R.determinant(), 1.0, 1e-14);
    EXPECT_LT((est.t - truth.t).norm(), 1e-10 * (1 + truth.t.norm()));
    for (size_t i = 0; i < src.size(); ++i) EXPECT_LT((est.Apply(src[i]) - dst[i]).norm(), 1e-9 * truth.s * 10);
  }
}

TEST(Sim3, EstimateWithNoiseIsCloseAndUnbiased) {
  std::mt19937 rng(3);
  const double sigma = 0.01;  // on a 10 m cloud of 200 points
  std::normal_distribution<double> noise(0.0, sigma);
  for (int trial = 0; trial < 20; ++trial) {
    const Sim3 truth = RandomSim3(rng);
    const std::vector<Eigen::Vector3d> src = RandomCloud(rng, 200, 10.0);
    std::vector<Eigen::Vector3d> dst;
    for (const auto& X : src) dst.push_back(truth.Apply(X) + truth.s * Eigen::Vector3d(noise(rng), noise(rng), noise(rng)));
    Sim3 est;
    ASSERT_TRUE(EstimateSim3(src, dst, &est));
    // Standard errors: scale ~ sigma / (spread sqrt(n)) ~ 1e-4, angle likewise.
    EXPECT_NEAR(est.s / truth.s, 1.0, 1e-3);
    EXPECT_LT(RotationAngle(est.R, truth.R), 1e-3);
    EXPECT_LT((est.t - truth.t).norm() / truth.s, 0.01);
    // Residual RMS close to the noise (3 dof per point minus 7 for the similarity).
    double ss = 0;
    for (size_t i = 0; i < src.size(); ++i) ss += (est.Apply(src[i]) - dst[i]).squaredNorm();
    const double rms = std::sqrt(ss / (3 * src.size())) / truth.s;
    EXPECT_NEAR(rms, sigma, 0.2 * sigma);
  }
}

TEST(Sim3, EstimateRejectsDegenerateInput) {
  std::mt19937 rng(4);
  Sim3 est;
  const std::vector<Eigen::Vector3d> two = {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0)};
  EXPECT_FALSE(EstimateSim3(two, two, &est));
  EXPECT_FALSE(EstimateSim3({}, {}, &est));
  // Size mismatch.
  const std::vector<Eigen::Vector3d> cloud = RandomCloud(rng, 10, 1.0);
  EXPECT_FALSE(EstimateSim3(cloud, std::vector<Eigen::Vector3d>(cloud.begin(), cloud.begin() + 9), &est));
  // Collinear (exactly and to 1e-12): the rotation about the line is free.
  std::vector<Eigen::Vector3d> line;
  const Eigen::Vector3d dir = RandomVector(rng, 1.0).normalized();
  for (int i = 0; i < 10; ++i) line.push_back(Eigen::Vector3d(1, 2, 3) + i * dir);
  EXPECT_FALSE(EstimateSim3(line, line, &est));
  std::vector<Eigen::Vector3d> nearly = line;
  nearly[3] += 1e-12 * dir.unitOrthogonal();
  EXPECT_FALSE(EstimateSim3(nearly, nearly, &est));
  // Coincident points.
  const std::vector<Eigen::Vector3d> same(5, Eigen::Vector3d(1, 1, 1));
  EXPECT_FALSE(EstimateSim3(same, same, &est));
  // Destination collapsed to a point: scale 0 is not a similarity.
  EXPECT_FALSE(EstimateSim3(cloud, std::vector<Eigen::Vector3d>(10, Eigen::Vector3d(1, 1, 1)), &est));
  // Non-finite input.
  std::vector<Eigen::Vector3d> bad = cloud;
  bad[2].x() = std::nan("");
  EXPECT_FALSE(EstimateSim3(bad, cloud, &est));
  EXPECT_FALSE(EstimateSim3(cloud, bad, &est));
  // Three non-collinear points are enough.
  const std::vector<Eigen::Vector3d> tri = {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0),
                                            Eigen::Vector3d(0, 1, 0)};
  EXPECT_TRUE(EstimateSim3(tri, tri, &est));
  EXPECT_NEAR(est.s, 1.0, 1e-14);
}

// Sim3::Apply(Pose) moves the camera with the world: a point's camera coordinates are
// preserved up to the scale s, and the two descriptions of a camera agree.
TEST(Sim3, ApplyToPoseConsistentWithPoints) {
  std::mt19937 rng(5);
  for (int trial = 0; trial < 100; ++trial) {
    const Sim3 S = RandomSim3(rng);
    const Pose pose = Pose::FromRC(RandomRotation(rng), RandomVector(rng, 10.0));
    const Pose moved = S.Apply(pose);
    EXPECT_LT((moved.C() - S.Apply(pose.C())).norm(), 1e-10 * (1 + moved.C().norm()));
    EXPECT_LT((moved.R() - pose.R() * S.R.transpose()).norm(), 1e-14);
    for (int k = 0; k < 5; ++k) {
      const Eigen::Vector3d X = RandomVector(rng, 10.0);
      const Eigen::Vector3d x = pose.ToCamera(X);
      EXPECT_LT((moved.ToCamera(S.Apply(X)) - S.s * x).norm(), 1e-9 * S.s * (1 + x.norm()));
    }
    // Round trip through the inverse and composition.
    const Pose back = S.Inverse().Apply(moved);
    EXPECT_LT((back.C() - pose.C()).norm(), 1e-9 * (1 + pose.C().norm()));
    EXPECT_LT(RotationAngle(back.R(), pose.R()), 1e-13);
    const Sim3 T = RandomSim3(rng);
    const Pose two = T.Apply(S.Apply(pose)), once = (T * S).Apply(pose);
    EXPECT_LT((two.C() - once.C()).norm(), 1e-9 * (1 + once.C().norm()));
    EXPECT_LT(RotationAngle(two.R(), once.R()), 1e-13);
  }
}

// Eq. 4's similarity of a motion: local poses made from global ones by a known similarity
// give it back to rounding, also when the centres lie on a line (a strip, a triplet of a
// video), where a centre-only fit would leave the roll about the line free.
TEST(FitMotionSimilarity, RecoversTheSimilarityOfExactLocalPosesEvenOnCollinearCentres) {
  std::mt19937 rng(7);
  for (const bool collinear : {false, true}) {
    for (int trial = 0; trial < 20; ++trial) {
      const Sim3 S = RandomSim3(rng);
      std::vector<Pose> global, local;
      const Eigen::Vector3d direction = RandomVector(rng, 1.0).normalized();
      for (int k = 0; k < 5; ++k) {
        const Eigen::Vector3d C = collinear ? Eigen::Vector3d(direction * (10.0 * k)) : RandomVector(rng, 20.0);
        global.push_back(Pose::FromRC(RandomRotation(rng), C));
        local.push_back(S.Apply(global.back()));
      }
      const MotionSimilarityFit fit = FitMotionSimilarity(global, local);
      ASSERT_TRUE(fit.scale_ok());
      const Sim3 est = fit.ToSim3();
      EXPECT_NEAR(est.s, S.s, 1e-12 * S.s);
      EXPECT_LT((est.R - S.R).norm(), 1e-12);
      for (const Pose& g : global) EXPECT_LT((est.Apply(g.C()) - S.Apply(g.C())).norm(), 1e-9 * (1.0 + S.t.norm()));
    }
  }
}

TEST(FitMotionSimilarity, CoincidentGlobalCentresHaveNoScale) {
  std::mt19937 rng(3);
  std::vector<Pose> global, local;
  for (int k = 0; k < 3; ++k) {
    global.push_back(Pose::FromRC(RandomRotation(rng), Eigen::Vector3d(1, 2, 3)));
    local.push_back(Pose::FromRC(RandomRotation(rng), RandomVector(rng, 1.0)));
  }
  EXPECT_FALSE(FitMotionSimilarity(global, local).scale_ok());
}

}  // namespace
}  // namespace pgba
