// The local Hessians under the redescending loss (LocalHessianOptions::loss "cauchy"): which
// observations they keep,
// where their points sit, and h and the robust cost against Ceres' own Cauchy cost.
#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <random>

#include "modules/local_hessian/local_bundle.h"
#include "modules/local_hessian/local_hessian.h"
#include "modules/local_hessian/reduced_camera_matrix.h"
#include "tests/local_hessian/dense_reference.h"
#include "tests/local_hessian/ring_scene.h"

namespace pgba {
namespace {

using testing::DenseCovariance;
using testing::MakeRingScene;
using testing::MakeTriplet;
using testing::RelativeDifference;
using testing::RingSceneOptions;

constexpr double kShiftPx = 6.0;  // beyond max_reprojection_px (4), within cauchy_max_reprojection_px (64)

// The ring scene with every 5th observation of image 2 moved by kShiftPx.
Reconstruction SceneWithShiftedObservations() {
  RingSceneOptions so;
  so.num_points = 600;
  so.seed = 11;
  Reconstruction rec = MakeRingScene(so);
  auto& points = rec.images.at(2).points2D;
  for (size_t i = 0; i < points.size(); i += 5) points[i].xy.x() += kShiftPx;
  return rec;
}

// Observations of `p` whose reprojection error exceeds `px` at its poses and points.
int ObservationsBeyond(const LocalBundleProblem& p, double px) {
  int n = 0;
  for (const LocalObservation& o : p.observations) {
    double r[2];
    ReprojectionError(p.cameras[o.view], p.poses[o.view].R0, o.pixel)(p.poses[o.view].x.data(),
                                                                      p.points[o.point].data(), r);
    n += std::hypot(r[0], r[1]) > px;
  }
  return n;
}

// The Huber problem drops the shifted observations at 4 px; the Cauchy problem keeps them,
// and each of its points sits at the minimum of the Cauchy cost over its observations, the
// poses held: Ceres, started there, neither lowers the cost nor moves a point.
TEST(CauchyLocalHessian, KeepsObservationsBeyondTheCutWithPointsAtTheLossMinimum) {
  const Reconstruction rec = SceneWithShiftedObservations();
  std::mt19937_64 rng(3);
  const LocalMotion t = MakeTriplet(rec, {1, 2, 4}, rng);
  LocalHessianOptions huber, cauchy;
  cauchy.loss.type = LossType::kCauchy;
  LocalBundleProblem ph, pc;
  ASSERT_EQ(BuildLocalBundleProblem(rec, t, huber, &ph), LocalHessianStatus::kOk);
  ASSERT_EQ(BuildLocalBundleProblem(rec, t, cauchy, &pc), LocalHessianStatus::kOk);
  EXPECT_EQ(ObservationsBeyond(ph, huber.max_reprojection_px), 0);
  const int kept_beyond = ObservationsBeyond(pc, huber.max_reprojection_px);
  EXPECT_GT(kept_beyond, 10);
  EXPECT_EQ(pc.observations.size(), ph.observations.size() + kept_beyond);
  EXPECT_EQ(ph.num_candidate_observations, pc.num_candidate_observations);

  std::vector<Eigen::Vector3d> points = pc.points;
  std::vector<PoseBlock> poses = pc.poses;
  ceres::Problem problem;
  for (auto& b : poses) {
    problem.AddParameterBlock(b.x.data(), 6);
    problem.SetParameterBlockConstant(b.x.data());
  }
  for (const LocalObservation& o : pc.observations)
    problem.AddResidualBlock(ReprojectionError::Create(pc.cameras[o.view], poses[o.view].R0, o.pixel),
                             pc.loss.CreateLossFunction(), poses[o.view].x.data(), points[o.point].data());
  ceres::Solver::Summary summary;
  ceres::Solve(testing::ConvergedSolverOptions(ceres::DENSE_SCHUR), &problem, &summary);
  EXPECT_LT(summary.initial_cost - summary.final_cost, 1e-9 * summary.initial_cost);
  double moved = 0.0;
  for (size_t i = 0; i < points.size(); ++i) moved = std::max(moved, (points[i] - pc.points[i]).norm());
  EXPECT_LT(moved, 1e-6 * MedianDepth(pc));  // ~1e-3 px; the 6 px observations alone pull a point ~0.05 px
}

// h under the Cauchy loss is the inverse of the camera block of the dense covariance built
// from Ceres' Jacobian of the Cauchy-robustified residuals (its loss correction), with
// observations in the loss's tail (beyond 4 px) taking part; RobustCost is twice Ceres' cost
// (1/2 sum rho) plus the capped loss of every candidate observation that was not kept.
TEST(CauchyLocalHessian, EqualsInverseOfCameraBlockOfDenseCovariance) {
  const Reconstruction rec = SceneWithShiftedObservations();
  std::mt19937_64 rng(3);
  const LocalMotion t = MakeTriplet(rec, {1, 2, 4}, rng);
  LocalHessianOptions opt = PaperTripletLocalHessianOptions();
  opt.loss.type = LossType::kCauchy;
  opt.solver.max_iterations = 5;
  LocalBundleProblem p;
  ASSERT_EQ(BuildLocalBundleProblem(rec, t, opt, &p), LocalHessianStatus::kOk);
  ASSERT_TRUE(SolveLocalBundle(opt.solver, &p));
  EXPECT_GT(ObservationsBeyond(p, opt.max_reprojection_px), 10);
  const ReducedCameraSystem red = ReducedCameraMatrix(p);
  const double L = MedianDepth(p);
  const GaugePrior prior = ComputeGaugePrior(red.h, p.poses, L, opt);
  const Matrix18d h = red.h + prior.P;
  const Eigen::MatrixXd cov = DenseCovariance(p, prior.P);
  ASSERT_GT(cov.rows(), 18);
  const Matrix18d h_ref = cov.topLeftCorner<18, 18>().fullPivLu().inverse();
  EXPECT_LT(RelativeDifference(h, h_ref, L), 1e-6);

  ceres::Problem problem;
  std::vector<PoseBlock> poses = p.poses;
  std::vector<Eigen::Vector3d> points = p.points;
  for (const LocalObservation& o : p.observations)
    problem.AddResidualBlock(ReprojectionError::Create(p.cameras[o.view], poses[o.view].R0, o.pixel),
                             p.loss.CreateLossFunction(), poses[o.view].x.data(), points[o.point].data());
  double ceres_cost = 0.0;
  ASSERT_TRUE(problem.Evaluate(ceres::Problem::EvaluateOptions(), &ceres_cost, nullptr, nullptr, nullptr));
  const double cap = opt.cauchy_max_reprojection_px / p.loss.scale;
  const int dropped = p.num_candidate_observations - static_cast<int>(p.observations.size());
  EXPECT_NEAR(RobustCost(p), 2.0 * ceres_cost + dropped * p.loss.scale * p.loss.scale * std::log1p(cap * cap),
              1e-9 * RobustCost(p));
}

}  // namespace
}  // namespace pgba
