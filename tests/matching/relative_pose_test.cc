#include "modules/matching/relative_pose.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "modules/matching/relative_pose_method.h"
#include "pgba/geometry/rotation.h"
#include "pgba/scene/camera.h"

namespace pgba {
namespace {

constexpr double kFocal = 1000.0;

Camera MakeCamera() {
  Camera c;
  c.model = CameraModel::kPinhole;
  c.width = 1600;
  c.height = 1200;
  c.params = {kFocal, kFocal, 800, 600};
  return c;
}

struct PairData {
  Eigen::Matrix3d R_21;
  Eigen::Vector3d t_21;  // unit
  std::vector<Eigen::Vector3d> b1, b2;
  std::vector<bool> is_inlier;
};

// Points in front of camera 1 (identity) seen by camera 2 at centre C2 with rotation R2;
// pixel noise `noise_px`, a fraction `outliers` of correspondences replaced by random pixels.
PairData MakePair(uint64_t seed, double noise_px, double outliers, int n, double rot_deg = 10.0) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0), depth(4.0, 8.0), unit(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, noise_px);
  const Camera cam = MakeCamera();
  PairData d;
  const Eigen::Vector3d C2(1.0, 0.2, 0.3);
  const Eigen::Matrix3d R2 = RandomRotationOfAngle(rng, rot_deg * M_PI / 180.0);
  d.R_21 = R2;
  d.t_21 = (-R2 * C2).normalized();
  while (static_cast<int>(d.b1.size()) < n) {
    const Eigen::Vector3d X(u(rng) * 3, u(rng) * 2, depth(rng));
    const Eigen::Vector3d x2 = R2 * (X - C2);
    if (x2.z() < 0.5) continue;
    Eigen::Vector2d p1 = cam.Project(X), p2 = cam.Project(x2);
    if (p2.x() < 0 || p2.y() < 0 || p2.x() > cam.width || p2.y() > cam.height) continue;
    const bool inlier = unit(rng) >= outliers;
    if (inlier) {
      p1 += Eigen::Vector2d(noise(rng), noise(rng));
      p2 += Eigen::Vector2d(noise(rng), noise(rng));
    } else {
      p2 = Eigen::Vector2d((u(rng) + 1) * 0.5 * cam.width, (u(rng) + 1) * 0.5 * cam.height);
    }
    d.b1.push_back(cam.PixelToBearing(p1));
    d.b2.push_back(cam.PixelToBearing(p2));
    d.is_inlier.push_back(inlier);
  }
  return d;
}

double AngleDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b)) * 180.0 / M_PI;
}

TEST(RelativePose, RecoversRotationAndDirectionWithNoiseAndOutliers) {
  for (const char* algorithm : {"stewenius", "nister"}) {
    for (uint64_t seed : {1, 2, 3}) {
      const PairData d = MakePair(seed, 0.5, 0.3, 400);
      RelativePoseOptions opt;
      opt.algorithm = algorithm;
      opt.seed = seed;
      const RelativePoseResult r = EstimateRelativePose(d.b1, d.b2, kFocal, opt);
      ASSERT_TRUE(r.success) << algorithm << " seed " << seed;
      const double rot_err = RotationAngleDeg(r.R_21, d.R_21);
      const double dir_err = AngleDeg(r.t_21, d.t_21);
      EXPECT_LT(rot_err, 0.05) << algorithm << " seed " << seed;
      EXPECT_LT(dir_err, 0.5) << algorithm << " seed " << seed;
      EXPECT_NEAR(r.t_21.norm(), 1.0, 1e-12);
      // The inlier mask matches the truth: nearly all true inliers found, few outliers
      // accepted (a random match can fall within 2 px of its epipolar line by chance).
      int tp = 0, fp = 0, n_in = 0;
      for (size_t i = 0; i < d.b1.size(); ++i) {
        n_in += d.is_inlier[i];
        if (r.inlier_mask[i]) (d.is_inlier[i] ? tp : fp)++;
      }
      EXPECT_GE(tp, 0.97 * n_in);
      EXPECT_LE(fp, 0.03 * (d.b1.size() - n_in) + 3);
      EXPECT_EQ(r.num_inliers, tp + fp);
      EXPECT_GT(r.median_triangulation_angle_deg, 3.0);  // baseline ~1 at depth 4-8
    }
  }
}

TEST(RelativePose, DeterministicForAGivenSeed) {
  const PairData d = MakePair(7, 0.5, 0.3, 300);
  RelativePoseOptions opt;
  opt.seed = 42;
  const RelativePoseResult a = EstimateRelativePose(d.b1, d.b2, kFocal, opt);
  const RelativePoseResult b = EstimateRelativePose(d.b1, d.b2, kFocal, opt);
  ASSERT_TRUE(a.success);
  EXPECT_EQ(a.R_21, b.R_21);
  EXPECT_EQ(a.t_21, b.t_21);
  EXPECT_EQ(a.inlier_mask, b.inlier_mask);
  EXPECT_EQ(a.ransac_iterations, b.ransac_iterations);
}

TEST(RelativePose, RefinementImprovesOnRansac) {
  // The minimal-sample RANSAC model alone vs. the refined one, averaged over seeds.
  double err_raw = 0, err_ref = 0;
  for (uint64_t seed = 10; seed < 16; ++seed) {
    const PairData d = MakePair(seed, 1.0, 0.1, 400);
    RelativePoseOptions opt;
    opt.seed = seed;
    opt.refine = false;
    err_raw += RotationAngleDeg(EstimateRelativePose(d.b1, d.b2, kFocal, opt).R_21, d.R_21);
    opt.refine = true;
    err_ref += RotationAngleDeg(EstimateRelativePose(d.b1, d.b2, kFocal, opt).R_21, d.R_21);
  }
  EXPECT_LT(err_ref, err_raw);
}

// From a pose 0.1 degree (1.7 px at this focal) and 1 degree (translation direction) off the
// truth, the refinement alone (no RANSAC) reaches RANSAC + refinement's accuracy and inlier
// set: what the view graph does with the front end's pose on the tracks' correspondences.
TEST(RelativePose, RefineFromAGivenPoseMatchesEstimation) {
  for (uint64_t seed : {1, 2, 3}) {
    const PairData d = MakePair(seed, 0.5, 0.3, 400);
    std::mt19937_64 rng(seed + 100);
    const Eigen::Matrix3d R0 = RandomRotationOfAngle(rng, 0.1 * M_PI / 180.0) * d.R_21;
    const Eigen::Vector3d t0 = RandomRotationOfAngle(rng, 1.0 * M_PI / 180.0) * d.t_21;
    RelativePoseOptions opt;
    opt.seed = seed;
    const RelativePoseResult est = EstimateRelativePose(d.b1, d.b2, kFocal, opt);
    const RelativePoseResult ref = RefineRelativePose(d.b1, d.b2, kFocal, opt, R0, t0);
    ASSERT_TRUE(ref.success) << "seed " << seed;
    EXPECT_EQ(ref.ransac_iterations, 0);
    EXPECT_LT(RotationAngleDeg(ref.R_21, d.R_21), 0.05) << "seed " << seed;
    EXPECT_LT(AngleDeg(ref.t_21, d.t_21), 0.5) << "seed " << seed;
    EXPECT_LT(RotationAngleDeg(ref.R_21, est.R_21), 0.01) << "seed " << seed;
    EXPECT_NEAR(ref.num_inliers, est.num_inliers, 0.01 * est.num_inliers) << "seed " << seed;
    EXPECT_NEAR(ref.median_triangulation_angle_deg, est.median_triangulation_angle_deg, 0.05);
  }
  // A start far from the truth finds no consensus: a failure, not a wrong pose.
  const PairData d = MakePair(4, 0.5, 0.3, 400);
  std::mt19937_64 rng(4);
  const RelativePoseResult bad =
      RefineRelativePose(d.b1, d.b2, kFocal, {}, RandomRotationOfAngle(rng, M_PI / 2) * d.R_21, d.t_21);
  EXPECT_FALSE(bad.success);
  EXPECT_THROW(RefineRelativePose(d.b1, d.b2, kFocal, {}, d.R_21, Eigen::Vector3d::Zero()), std::invalid_argument);
}

TEST(RelativePose, PureRotationHasTinyTriangulationAngle) {
  std::mt19937_64 rng(5);
  const Camera cam = MakeCamera();
  const Eigen::Matrix3d R = RandomRotationOfAngle(rng, 0.2);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::normal_distribution<double> noise(0.0, 0.5);
  std::vector<Eigen::Vector3d> b1, b2;
  while (b1.size() < 200) {
    const Eigen::Vector3d X(u(rng) * 3, u(rng) * 2, 6.0 + u(rng));
    const Eigen::Vector3d x2 = R * X;
    const Eigen::Vector2d p2 = cam.Project(x2);
    if (x2.z() < 0.5 || p2.x() < 0 || p2.y() < 0 || p2.x() > cam.width || p2.y() > cam.height) continue;
    b1.push_back(cam.PixelToBearing(cam.Project(X) + Eigen::Vector2d(noise(rng), noise(rng))));
    b2.push_back(cam.PixelToBearing(p2 + Eigen::Vector2d(noise(rng), noise(rng))));
  }
  const RelativePoseResult r = EstimateRelativePose(b1, b2, kFocal, {});
  // Whatever translation RANSAC fits to the noise, the rays are parallel: angle ~ noise.
  if (r.success) {
    EXPECT_LT(r.median_triangulation_angle_deg, 0.1);
    EXPECT_LT(RotationAngleDeg(r.R_21, R), 0.1);
  }
}

TEST(RelativePose, FailsCleanlyOnTooFewOrBadInput) {
  const PairData d = MakePair(3, 0.5, 0.0, 7);
  EXPECT_FALSE(EstimateRelativePose(d.b1, d.b2, kFocal, {}).success);
  EXPECT_FALSE(EstimateRelativePose({}, {}, kFocal, {}).success);
  // Pure outliers: no consistent model with enough support.
  const PairData junk = MakePair(4, 0.5, 1.0, 200);
  const RelativePoseResult r = EstimateRelativePose(junk.b1, junk.b2, kFocal, {});
  EXPECT_LT(r.num_inliers, 60);
  EXPECT_THROW(EstimateRelativePose(d.b1, {}, kFocal, {}), std::invalid_argument);
  EXPECT_THROW(EstimateRelativePose(d.b1, d.b2, 0.0, {}), std::invalid_argument);
  RelativePoseOptions bad;
  bad.algorithm = "sevenpoint";
  const PairData ok = MakePair(3, 0.5, 0.0, 50);
  EXPECT_THROW(EstimateRelativePose(ok.b1, ok.b2, kFocal, bad), std::invalid_argument);
}

// Every name of the method tables (the config check's choices) is accepted by the estimator
// with either scoring, and a name outside them is refused by both scorings' parsers with the
// table's own list (relative_pose_method.h).
TEST(RelativePose, EveryMethodNameIsAcceptedAndOthersAreRefusedWithTheList) {
  const PairData d = MakePair(5, 0.5, 0.1, 100);
  for (const auto& [scoring, scoring_name] : kPoseScoringNames)
    for (const auto& [solver, solver_name] : kPoseSolverNames) {
      RelativePoseOptions o;
      o.scoring = std::string(scoring_name);
      o.algorithm = std::string(solver_name);
      EXPECT_EQ(ParsePoseScoring(o.scoring), scoring);
      EXPECT_EQ(ParsePoseSolver(o.algorithm), solver);
      const RelativePoseResult r = EstimateRelativePose(d.b1, d.b2, kFocal, o);
      EXPECT_TRUE(r.success) << o.scoring << " " << o.algorithm;
      EXPECT_LT(AngleDeg(r.t_21, d.t_21), 2.0) << o.scoring << " " << o.algorithm;
    }
  EXPECT_EQ(MethodNames(kPoseScoringNames), (std::vector<std::string>{"sampson", "opengv"}));
  for (const char* scoring : {"sampson", "opengv"}) {
    RelativePoseOptions o;
    o.scoring = scoring;
    o.algorithm = "8point";
    try {
      EstimateRelativePose(d.b1, d.b2, kFocal, o);
      ADD_FAILURE() << "no exception for algorithm 8point with " << scoring;
    } catch (const std::invalid_argument& e) {
      EXPECT_EQ(std::string(e.what()), "unknown relative pose algorithm '8point' (stewenius, nister)");
    }
  }
  RelativePoseOptions o;
  o.scoring = "samspon";
  EXPECT_THROW(EstimateRelativePose(d.b1, d.b2, kFocal, o), std::invalid_argument);
}

TEST(RelativePose, SampsonAngleApproximatesTwoViewReprojectionError) {
  // Rotate the second bearing of an exact correspondence by delta out of its epipolar
  // plane. The Sampson error estimates the smallest total displacement of both bearings
  // that restores the epipolar constraint: at most delta (moving b2 back), and not much
  // less here since both views see the point at similar angles to the baseline. Moving
  // within the epipolar plane costs nothing.
  const PairData d = MakePair(8, 0.0, 0.0, 20);
  const double delta = 3.0 / kFocal;
  for (size_t i = 0; i < d.b1.size(); ++i) {
    EXPECT_LT(std::abs(SampsonAngle(d.R_21, d.t_21, d.b1[i], d.b2[i])) * kFocal, 1e-6);
    const Eigen::Vector3d normal = d.t_21.cross(d.R_21 * d.b1[i]).normalized();  // of the epipolar plane
    const Eigen::Vector3d out = std::cos(delta) * d.b2[i] + std::sin(delta) * normal;
    const double e = std::abs(SampsonAngle(d.R_21, d.t_21, d.b1[i], out));
    EXPECT_GT(e, 0.5 * delta);
    EXPECT_LT(e, 1.001 * delta);
    const Eigen::Vector3d in_plane = (d.b2[i] + delta * normal.cross(d.b2[i])).normalized();
    EXPECT_LT(std::abs(SampsonAngle(d.R_21, d.t_21, d.b1[i], in_plane)), 1e-3 * delta);
  }
}

TEST(RelativePose, CheiralityRejectsPointsBehind) {
  const Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  const Eigen::Vector3d C2(1, 0, 0), t = -C2;
  const Eigen::Vector3d X(0.5, 0, 5), Y(0.5, 0, -5);
  EXPECT_TRUE(InFrontOfBoth(R, t, X.normalized(), (X - C2).normalized(), 1e-6));
  // A point behind both cameras projects to the pixels of its mirror image: the bearings
  // computed from those pixels point away from it.
  EXPECT_FALSE(InFrontOfBoth(R, t, -Y.normalized(), -(Y - C2).normalized(), 1e-6));
  // Behind one camera only.
  const Eigen::Vector3d Z(3.0, 0, 1.0);
  const Eigen::Matrix3d R2 = ExpSO3(Eigen::Vector3d(0, M_PI, 0));  // camera 2 looks backwards
  const Eigen::Vector3d t2 = -R2 * C2;
  const Eigen::Vector3d z2 = R2 * (Z - C2);
  EXPECT_TRUE(InFrontOfBoth(R2, t2, Z.normalized(), z2.normalized(), 1e-6));
  EXPECT_FALSE(InFrontOfBoth(R2, t2, Z.normalized(), -z2.normalized(), 1e-6));
}

}  // namespace
}  // namespace pgba
