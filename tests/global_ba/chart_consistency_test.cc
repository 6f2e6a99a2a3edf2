// (b) The 6-vector chart of the local Hessian and of the global residual are the same: moving
// one global pose changes the global residual's cost (the triplet similarity re-adapted, as
// in the global BA, which also cancels the gauge prior) exactly as the reprojection cost
// (points re-optimised) of the triplet changes, to second order. The truth side goes
// through Sim3::Apply and the reprojection cost, never through either chart.
#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include <random>

#include "modules/global_ba/motion_residual.h"
#include "modules/global_ba/motion_similarity.h"
#include "modules/global_ba/motion_weighting.h"
#include "modules/local_hessian/local_bundle.h"
#include "tests/local_hessian/dense_reference.h"
#include "tests/local_hessian/ring_scene.h"

namespace pgba {
namespace {

using testing::ConvergedSolverOptions;
using testing::CostWithPointsOptimised;
using testing::MakeRingScene;
using testing::MakeTriplet;
using testing::RingSceneOptions;

TEST(ChartConsistency, GlobalResidualPredictsReprojectionCost) {
  RingSceneOptions so;
  so.num_points = 600;
  so.noise_px = 0.0;
  so.seed = 21;
  const Reconstruction rec = MakeRingScene(so);
  std::mt19937_64 rng(13);
  const LocalMotion t = MakeTriplet(rec, {5, 6, 8}, rng);
  const LocalHessian lh = ComputeLocalHessian(rec, t, 0, PaperTripletLocalHessianOptions());
  ASSERT_EQ(lh.status, LocalHessianStatus::kOk);
  LocalMotion t0 = t;
  t0.local_poses = lh.local_poses;
  LocalBundleProblem p;
  ASSERT_EQ(BuildLocalBundleProblem(rec, t0, PaperTripletLocalHessianOptions(), &p), LocalHessianStatus::kOk);

  // Global side: true poses, the exact similarity, W = D V.
  std::vector<Pose> global(3);
  std::vector<PoseBlock> blocks(3);
  std::vector<Eigen::Matrix3d> R0(3);
  for (int k = 0; k < 3; ++k) {
    global[k] = rec.images.at(t.image_ids[k]).pose;
    blocks[k] = PoseBlock::FromPose(global[k]);
    R0[k] = blocks[k].R0;
  }
  const MotionSimilarity sim = SimilarityFromSim3(global, t.global_to_local);
  const MotionWeight W = MotionWeightOf(lh, PaperTripletGlobalBAOptions(), /*factored=*/true);
  // Global cost with the poses fixed and the similarity minimised over.
  auto global_cost = [&](std::vector<PoseBlock> b) {
    MotionSimilarity s = sim;
    ceres::Problem problem;
    problem.AddResidualBlock(new MotionResidual(R0, sim, lh.local_poses, W), nullptr, b[0].x.data(), b[1].x.data(),
                             b[2].x.data(), s.x.data());
    for (auto& block : b) problem.SetParameterBlockConstant(block.x.data());
    ceres::Solver::Summary summary;
    ceres::Solve(ConvergedSolverOptions(ceres::DENSE_QR), &problem, &summary);
    return summary.final_cost;
  };
  EXPECT_LT(global_cost(blocks), 1e-14);

  std::normal_distribution<double> n(0.0, 1.0);
  int checked = 0;
  for (int view = 0; view < 3; ++view) {
    for (int trial = 0; trial < 4; ++trial) {
      // A random direction of the global 6-vector of one view; trials 0-1 positions only,
      // 2-3 rotations only, so that both halves are checked on their own.
      PoseVector dir = PoseVector::Zero();
      for (int i = 0; i < 3; ++i) dir(trial < 2 ? i : 3 + i) = n(rng);
      dir.normalize();
      // Step size for a cost increase of ~1e-4 (second-order regime).
      std::vector<PoseBlock> moved = blocks;
      moved[view].x += 1e-6 * dir;
      const double c1 = global_cost(moved);
      const double eps = 1e-6 * std::sqrt(1e-4 / c1);
      moved = blocks;
      moved[view].x += eps * dir;
      const double predicted = global_cost(moved);
      // Truth: local poses = similarity applied to the moved global poses; reprojection cost.
      std::vector<Pose> local(3);
      for (int k = 0; k < 3; ++k) local[k] = t.global_to_local.Apply(moved[k].ToPose());
      const double actual = CostWithPointsOptimised(p, local);
      EXPECT_NEAR(predicted / actual, 1.0, 2e-3) << "view " << view << " trial " << trial;
      ++checked;
      // Power of the test: the same move read in a wrong chart (rotation increment on the
      // left, R = Exp(omega) R0) is not what the residual predicts.
      if (trial >= 2) {
        std::vector<Pose> wrong = local;
        const Pose g = Pose::FromRC(ExpSO3(eps * dir.tail<3>()) * blocks[view].R0, blocks[view].x.head<3>());
        wrong[view] = t.global_to_local.Apply(g);
        EXPECT_GT(std::abs(CostWithPointsOptimised(p, wrong) / predicted - 1.0), 0.05);
      }
    }
  }
  EXPECT_EQ(checked, 12);
}

}  // namespace
}  // namespace pgba
