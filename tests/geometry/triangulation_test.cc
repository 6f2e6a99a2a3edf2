// Triangulation against synthetic truth: exact recovery without noise, statistically
// consistent errors with noise (chi-square of the 3D error under the predicted covariance),
// robustness to a gross outlier, and rejection of unobservable configurations.
#include "pgba/geometry/triangulation.h"

#include <gtest/gtest.h>

#include <random>

#include "pgba/geometry/rotation.h"

namespace pgba {
namespace {

Camera MakeCamera(CameraModel model) {
  Camera c;
  c.model = model;
  c.width = 1920;
  c.height = 1080;
  switch (model) {
    case CameraModel::kSimplePinhole: c.params = {1000, 960, 540}; break;
    case CameraModel::kPinhole: c.params = {1000, 1010, 955, 545}; break;
    case CameraModel::kSimpleRadial: c.params = {1000, 960, 540, -0.08}; break;
    case CameraModel::kRadial: c.params = {1000, 960, 540, -0.1, 0.03}; break;
    case CameraModel::kOpenCV: c.params = {1000, 1010, 955, 545, -0.1, 0.03, 0.001, -0.002}; break;
  }
  return c;
}

// A camera at `C` looking at `target`, with its rotation about the optical axis and the
// aim jittered a little, so the point is not at the principal point.
Pose LookAt(std::mt19937& rng, const Eigen::Vector3d& C, const Eigen::Vector3d& target) {
  const Eigen::Vector3d z = (target - C).normalized();
  const Eigen::Vector3d x = z.unitOrthogonal();
  Eigen::Matrix3d R;  // rows: camera axes in the world
  R.row(0) = x.transpose();
  R.row(1) = z.cross(x).transpose();
  R.row(2) = z.transpose();
  std::uniform_real_distribution<double> roll(-M_PI, M_PI), aim(-0.2, 0.2);
  R = ExpSO3(Eigen::Vector3d(aim(rng), aim(rng), roll(rng))) * R;
  return Pose::FromRC(R, C);
}

struct Scene {
  Eigen::Vector3d X;
  std::vector<TrackView> views;
};

// n cameras at distance ~10 around a point, spread over a cone of +-30 degrees.
Scene MakeScene(std::mt19937& rng, const Camera* camera, int n) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Scene s;
  s.X = Eigen::Vector3d(u(rng), u(rng), u(rng));
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d dir = Eigen::Vector3d(0.5 * u(rng), 0.5 * u(rng), -1.0).normalized();
    const Eigen::Vector3d C = s.X + (10.0 + 2.0 * u(rng)) * dir;
    TrackView v;
    v.pose = LookAt(rng, C, s.X);
    v.camera = camera;
    v.pixel = camera->Project(v.pose.ToCamera(s.X));
    s.views.push_back(v);
  }
  return s;
}

// d pixel / d X by central differences, for the predicted covariance.
Eigen::Matrix<double, 2, 3> NumericJacobian(const TrackView& v, const Eigen::Vector3d& X) {
  Eigen::Matrix<double, 2, 3> J;
  for (int k = 0; k < 3; ++k) {
    Eigen::Vector3d d = Eigen::Vector3d::Zero();
    d(k) = 1e-6;
    J.col(k) = (v.camera->Project(v.pose.ToCamera(X + d)) - v.camera->Project(v.pose.ToCamera(X - d))) / 2e-6;
  }
  return J;
}

TEST(Triangulation, LinearTwoAndManyViewsExact) {
  std::mt19937 rng(1);
  const Camera cam = MakeCamera(CameraModel::kPinhole);
  for (int n : {2, 3, 5, 20}) {
    for (int trial = 0; trial < 50; ++trial) {
      const Scene s = MakeScene(rng, &cam, n);
      std::vector<Pose> poses;
      std::vector<Eigen::Vector3d> bearings;
      for (const auto& v : s.views) {
        poses.push_back(v.pose);
        bearings.push_back(cam.PixelToBearing(v.pixel));
      }
      Eigen::Vector3d X;
      ASSERT_TRUE(TriangulateLinear(poses, bearings, &X));
      EXPECT_LT((X - s.X).norm(), 1e-10) << n;
    }
  }
  Eigen::Vector3d X;
  EXPECT_FALSE(TriangulateLinear({Pose()}, {Eigen::Vector3d::UnitZ()}, &X));
}

// Georeferenced scenes (UTM-like coordinates, 1e6 m from the origin, cameras 10 m from the
// point): the result must still be exact to the scene's scale, not to the coordinates'.
TEST(Triangulation, FarFromOriginExact) {
  std::mt19937 rng(11);
  const Camera cam = MakeCamera(CameraModel::kPinhole);
  const Eigen::Vector3d offset(4.5e6, -3.2e6, 1.2e3);
  for (int n : {2, 3, 6}) {
    for (int trial = 0; trial < 50; ++trial) {
      Scene s = MakeScene(rng, &cam, n);
      s.X += offset;
      for (auto& v : s.views) v.pose = Pose::FromRC(v.pose.R(), v.pose.C() + offset);
      std::vector<Pose> poses;
      std::vector<Eigen::Vector3d> bearings;
      for (const auto& v : s.views) {
        poses.push_back(v.pose);
        bearings.push_back(cam.PixelToBearing(v.pixel));
      }
      Eigen::Vector3d X;
      ASSERT_TRUE(TriangulateLinear(poses, bearings, &X)) << n;
      EXPECT_LT((X - s.X).norm(), 1e-7) << n;  // 1e-13 of the coordinates (rounding: 1e-10 m)
      const TriangulatedPoint p = TriangulateTrack(s.views);
      ASSERT_TRUE(p.ok);
      EXPECT_LT((p.X - s.X).norm(), 1e-6) << n;
      for (double r : p.residuals_px) EXPECT_LT(r, 1e-3);
    }
  }
}

TEST(Triangulation, TrackExactWithoutNoiseForEveryCameraModel) {
  std::mt19937 rng(2);
  for (CameraModel model : {CameraModel::kSimplePinhole, CameraModel::kPinhole, CameraModel::kSimpleRadial,
                            CameraModel::kRadial, CameraModel::kOpenCV}) {
    const Camera cam = MakeCamera(model);
    for (int n : {2, 3, 7}) {
      for (int trial = 0; trial < 30; ++trial) {
        const Scene s = MakeScene(rng, &cam, n);
        const TriangulatedPoint p = TriangulateTrack(s.views);
        ASSERT_TRUE(p.ok) << CameraModelName(model) << " n=" << n;
        EXPECT_LT((p.X - s.X).norm(), 1e-9) << CameraModelName(model);
        ASSERT_EQ(p.residuals_px.size(), s.views.size());
        for (double r : p.residuals_px) EXPECT_LT(r, 1e-6);
        EXPECT_NEAR(p.max_angle_deg, MaxTriangulationAngleDeg(s.views, s.X), 1e-6);
      }
    }
  }
}

// With Gaussian pixel noise the ML estimate's error e follows N(0, sigma^2 (J^T J)^-1):
// e^T (J^T J) e / sigma^2 is chi-square with 3 dof (mean 3). This checks that the result
// is at the noise level, neither biased nor worse than optimal.
TEST(Triangulation, ErrorsAtNoiseLevel) {
  std::mt19937 rng(3);
  const Camera cam = MakeCamera(CameraModel::kOpenCV);
  const double sigma = 0.7;
  std::normal_distribution<double> noise(0.0, sigma);
  for (int n : {2, 4, 8}) {
    double chi2_sum = 0.0, res2_sum = 0.0;
    int res_count = 0;
    const int trials = 400;
    for (int trial = 0; trial < trials; ++trial) {
      Scene s = MakeScene(rng, &cam, n);
      for (auto& v : s.views) v.pixel += Eigen::Vector2d(noise(rng), noise(rng));
      TriangulationOptions opt;
      opt.huber_px = 100.0;  // pure least squares: Gaussian noise, no outliers
      opt.outlier_px = 100.0;
      const TriangulatedPoint p = TriangulateTrack(s.views, opt);
      ASSERT_TRUE(p.ok);
      Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
      for (const auto& v : s.views) {
        const Eigen::Matrix<double, 2, 3> J = NumericJacobian(v, s.X);
        H += J.transpose() * J;
      }
      const Eigen::Vector3d e = p.X - s.X;
      chi2_sum += e.dot(H * e) / (sigma * sigma);
      for (double r : p.residuals_px) res2_sum += r * r;
      res_count += n;
    }
    // Mean of 400 chi2(3) draws: 3 +- 0.12 (1 sd).
    EXPECT_NEAR(chi2_sum / trials, 3.0, 0.5) << "n=" << n;
    // Residuals: E[sum r^2] = sigma^2 (2n - 3).
    EXPECT_NEAR(res2_sum / res_count, sigma * sigma * (2.0 * n - 3) / n, 0.12 * sigma * sigma) << "n=" << n;
  }
}

// One gross outlier among 5 views: the result is the inliers' estimate, and the outlier's
// residual is flagged (above outlier_px) while the inliers' are at the noise level.
TEST(Triangulation, RobustToOneGrossOutlier) {
  std::mt19937 rng(4);
  const Camera cam = MakeCamera(CameraModel::kPinhole);
  std::normal_distribution<double> noise(0.0, 0.5);
  std::uniform_real_distribution<double> ux(0, 1920), uy(0, 1080);
  std::uniform_int_distribution<int> which(0, 4);
  int checked = 0;
  for (int trial = 0; trial < 300; ++trial) {
    Scene s = MakeScene(rng, &cam, 5);
    for (auto& v : s.views) v.pixel += Eigen::Vector2d(noise(rng), noise(rng));
    const int bad = which(rng);
    const Eigen::Vector2d true_px = s.views[bad].pixel;
    s.views[bad].pixel = Eigen::Vector2d(ux(rng), uy(rng));
    if ((s.views[bad].pixel - true_px).norm() < 50.0) continue;  // not gross
    ++checked;
    const TriangulatedPoint p = TriangulateTrack(s.views);
    ASSERT_TRUE(p.ok) << trial;
    // Reference: the same triangulation on the four inliers only.
    std::vector<TrackView> inliers = s.views;
    inliers.erase(inliers.begin() + bad);
    const TriangulatedPoint ref = TriangulateTrack(inliers);
    ASSERT_TRUE(ref.ok);
    EXPECT_LT((p.X - ref.X).norm(), 1e-6) << trial;
    EXPECT_LT((p.X - s.X).norm(), 0.05) << trial;  // ~10 sd of a 0.5 px, 10 m configuration
    for (int i = 0; i < 5; ++i) {
      if (i == bad)
        EXPECT_GT(p.residuals_px[i], 4.0) << trial;
      else
        EXPECT_LT(p.residuals_px[i], 3.0) << trial;
    }
  }
  EXPECT_GT(checked, 250);
}

// A start near the solution (a previous pass's point, the poses since moved a little): the
// refinement from it reaches the point the full search finds, outlier flagged, without the
// search; a start whose refinement keeps fewer views than it claims (a point that another
// basin would decide) falls back to the full search, the same bits as TriangulateTrack.
TEST(Triangulation, FromAStartReachesTheFullSearchsPointOrFallsBackToIt) {
  std::mt19937 rng(11);
  const Camera cam = MakeCamera(CameraModel::kPinhole);
  std::normal_distribution<double> noise(0.0, 0.5);
  for (int trial = 0; trial < 100; ++trial) {
    Scene s = MakeScene(rng, &cam, 6);
    for (auto& v : s.views) v.pixel += Eigen::Vector2d(noise(rng), noise(rng));
    s.views[trial % 6].pixel += Eigen::Vector2d(300.0, -200.0);  // one gross outlier
    const TriangulatedPoint full = TriangulateTrack(s.views);
    ASSERT_TRUE(full.ok) << trial;
    PointStart near;
    near.X = full.X + Eigen::Vector3d(0.01, -0.02, 0.015);  // ~0.5 px at 10 m, focal ~1000 px
    near.support = 5;
    const TriangulatedPoint warm = TriangulateTrackFrom(s.views, near);
    ASSERT_TRUE(warm.ok) << trial;
    EXPECT_LT((warm.X - full.X).norm(), 1e-7) << trial;
    EXPECT_GT(warm.residuals_px[trial % 6], 4.0) << trial;

    PointStart far;
    far.X = full.X + Eigen::Vector3d(0.0, 0.0, 40.0);  // behind or far off every camera's ray
    far.support = 6;  // more than the refinement can keep: the outlier stays out
    const TriangulatedPoint fallback = TriangulateTrackFrom(s.views, far);
    ASSERT_TRUE(fallback.ok) << trial;
    EXPECT_EQ(fallback.X, full.X) << trial;
  }
}

// A long track (80 views, more than the consensus samples) with 30% gross outliers: the
// inliers' estimate is recovered and exactly the outliers are flagged.
TEST(Triangulation, LongTrackWithManyOutliers) {
  std::mt19937 rng(12);
  const Camera cam = MakeCamera(CameraModel::kSimpleRadial);
  std::normal_distribution<double> noise(0.0, 0.5);
  std::uniform_real_distribution<double> ux(0, 1920), uy(0, 1080);
  for (int trial = 0; trial < 10; ++trial) {
    Scene s = MakeScene(rng, &cam, 80);
    std::vector<bool> bad(80, false);
    for (size_t i = 0; i < s.views.size(); ++i) {
      const Eigen::Vector2d clean = s.views[i].pixel;
      s.views[i].pixel += Eigen::Vector2d(noise(rng), noise(rng));
      if (i % 10 < 3) {
        do s.views[i].pixel = Eigen::Vector2d(ux(rng), uy(rng));
        while ((s.views[i].pixel - clean).norm() < 20.0);
        bad[i] = true;
      }
    }
    const TriangulatedPoint p = TriangulateTrack(s.views);
    ASSERT_TRUE(p.ok);
    EXPECT_LT((p.X - s.X).norm(), 0.01);
    for (size_t i = 0; i < s.views.size(); ++i) EXPECT_EQ(p.residuals_px[i] > 4.0, bad[i]) << i;
  }
}

// Turning a camera by 180 degrees about its y axis puts the point behind it while its
// observation stays on the same line through the centre (the backward ray): algebraically
// the rays still intersect at the point, only the cheirality test can reject it.
void TurnAway(const Eigen::Vector3d& X, TrackView* v) {
  const Eigen::Matrix3d flip = Eigen::Vector3d(-1, 1, -1).asDiagonal();
  v->pose = Pose::FromRC(flip * v->pose.R(), v->pose.C());
  ASSERT_LT(v->pose.ToCamera(X).z(), 0);
  v->pixel = v->camera->Project(v->pose.ToCamera(X));
}

TEST(Triangulation, RejectsPointBehindCameras) {
  std::mt19937 rng(5);
  const Camera cam = MakeCamera(CameraModel::kPinhole);
  for (int trial = 0; trial < 50; ++trial) {
    // Behind both cameras of a pair, and behind every camera of a triple.
    for (int n : {2, 3}) {
      Scene s = MakeScene(rng, &cam, n);
      for (auto& v : s.views) TurnAway(s.X, &v);
      EXPECT_FALSE(TriangulateTrack(s.views).ok) << trial;
    }
    // Behind one camera of a pair: no two views agree.
    Scene s2 = MakeScene(rng, &cam, 2);
    TurnAway(s2.X, &s2.views[1]);
    EXPECT_FALSE(TriangulateTrack(s2.views).ok) << trial;
    // One camera of three turned away: the other two still triangulate the point, and the
    // third is flagged (its observation cannot come from a point in front of it).
    Scene s3 = MakeScene(rng, &cam, 3);
    TurnAway(s3.X, &s3.views[0]);
    const TriangulatedPoint p3 = TriangulateTrack(s3.views);
    ASSERT_TRUE(p3.ok) << trial;
    EXPECT_LT((p3.X - s3.X).norm(), 1e-9);
    EXPECT_GT(p3.residuals_px[0], 1e3);
    EXPECT_LT(p3.residuals_px[1], 1e-6);
  }
}

TEST(Triangulation, RejectsParallelRaysAndSmallAngles) {
  const Camera cam = MakeCamera(CameraModel::kPinhole);
  // Two cameras with the same orientation, 1 m apart, both seeing the principal point:
  // parallel rays, the point is at infinity.
  std::vector<TrackView> views(2);
  for (int i = 0; i < 2; ++i) {
    views[i].pose = Pose::FromRC(Eigen::Matrix3d::Identity(), Eigen::Vector3d(i, 0, 0));
    views[i].camera = &cam;
    views[i].pixel = Eigen::Vector2d(cam.params[2], cam.params[3]);
  }
  EXPECT_FALSE(TriangulateTrack(views).ok);
  // Same camera twice (zero baseline).
  views[1].pose = views[0].pose;
  views[1].pixel = views[0].pixel + Eigen::Vector2d(0.3, 0.0);
  EXPECT_FALSE(TriangulateTrack(views).ok);
  // A valid point seen at a small angle is rejected only below min_angle_deg.
  const Eigen::Vector3d X(0.05, 0, 100);  // baseline 1 m at 100 m: ~0.57 degrees
  views[1].pose = Pose::FromRC(Eigen::Matrix3d::Identity(), Eigen::Vector3d(1, 0, 0));
  for (auto& v : views) v.pixel = cam.Project(v.pose.ToCamera(X));
  TriangulationOptions opt;
  const TriangulatedPoint p = TriangulateTrack(views, opt);
  ASSERT_TRUE(p.ok);
  EXPECT_LT((p.X - X).norm(), 1e-6);
  EXPECT_NEAR(p.max_angle_deg, std::atan2(1.0, 100.0) * 180 / M_PI, 1e-4);
  opt.min_angle_deg = 1.0;
  EXPECT_FALSE(TriangulateTrack(views, opt).ok);
  // Fewer than two views.
  EXPECT_FALSE(TriangulateTrack({views[0]}).ok);
  EXPECT_FALSE(TriangulateTrack({}).ok);
}

TEST(Triangulation, MaxAngleAnalytic) {
  const Camera cam = MakeCamera(CameraModel::kPinhole);
  std::vector<TrackView> views(3);
  views[0].pose = Pose::FromRC(Eigen::Matrix3d::Identity(), Eigen::Vector3d(-1, 0, 0));
  views[1].pose = Pose::FromRC(Eigen::Matrix3d::Identity(), Eigen::Vector3d(1, 0, 0));
  views[2].pose = Pose::FromRC(Eigen::Matrix3d::Identity(), Eigen::Vector3d(0, 0, 0));
  for (auto& v : views) v.camera = &cam;
  EXPECT_NEAR(MaxTriangulationAngleDeg(views, Eigen::Vector3d(0, 0, 1)), 90.0, 1e-12);
  EXPECT_NEAR(MaxTriangulationAngleDeg(views, Eigen::Vector3d(0, 0, std::sqrt(3.0))), 60.0, 1e-12);
}

}  // namespace
}  // namespace pgba
