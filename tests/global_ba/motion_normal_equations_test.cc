// The motion-block solver of the pointless global BA (motion_normal_equations.h) against
// Ceres on the same objective: whole-track motions of a ring, local Hessians taken at
// perturbed poses. Both solvers minimise sum_s |W_s (x_s - x0_s - n_s)|^2; the gauge is held
// differently (a pose and a scale for the block solver, the reference motion's similarity
// for Ceres), so the solutions are compared by what no gauge changes: the final cost and the
// relative poses of every image pair.
#include "modules/global_ba/motion_normal_equations.h"

#include <gtest/gtest.h>

#include <cstdio>

#include "evaluation/ground_truth.h"
#include "modules/global_ba/global_ba.h"
#include "modules/local_hessian/whole_track_motions.h"
#include "modules/mapper/pose_refinement.h"
#include "tests/global_ba/global_ba_fixture.h"
#include "tests/local_hessian/ring_scene.h"

namespace pgba {
namespace {

using testing::MakeRingScene;
using testing::PerturbPoses;
using testing::PosesOf;
using testing::RingSceneOptions;

// An 18-view ring (0.5 px noise), its poses perturbed, whole-track motions of up to 6 views
// and their local Hessians taken at the perturbed poses.
struct RingMotions {
  Reconstruction rec;
  std::map<uint32_t, Pose> truth, initial;
  std::vector<LocalMotion> motions;
  LocalHessianResult hessians;
};

RingMotions MakeRingMotions() {
  RingSceneOptions ro;
  ro.num_images = 18;
  ro.num_points = 1500;
  ro.noise_px = 0.5;
  ro.seed = 11;
  RingMotions r;
  r.rec = MakeRingScene(ro);
  r.truth = PosesOf(r.rec);
  r.initial = PerturbPoses(r.truth, 0.3, 0.01, 3);
  WholeTrackMotionOptions mo;
  mo.max_views = 6;
  r.motions = SelectWholeTrackMotions(r.rec, r.initial, mo);
  r.hessians = ComputeLocalHessians(r.rec, r.motions, LocalHessianOptions());
  return r;
}

TEST(MotionBlockSolver, SameSolutionAsCeresOnTheSameObjective) {
  const RingMotions ring = MakeRingMotions();
  const Reconstruction& rec = ring.rec;
  const std::map<uint32_t, Pose>& truth = ring.truth;
  const std::map<uint32_t, Pose>& initial = ring.initial;
  const std::vector<LocalMotion>& motions = ring.motions;
  const LocalHessianResult& hessians = ring.hessians;
  ASSERT_EQ(hessians.num_ok(), static_cast<int>(motions.size()));

  GlobalBAOptions blocks = GlobalBAOptions();
  blocks.solver.function_tolerance = 1e-12;
  blocks.solver.parameter_tolerance = 1e-14;
  blocks.solver.max_iterations = 50;
  GlobalBAOptions ceres = blocks;
  ceres.gauge = GaugeFixing::kFixSimilarity;  // not supported by the block solver: Ceres runs
  const GlobalBAResult a = PointlessGlobalBA(initial, motions, hessians.hessians, blocks);
  const GlobalBAResult b = PointlessGlobalBA(initial, motions, hessians.hessians, ceres);
  ASSERT_EQ(a.poses.size(), truth.size());
  ASSERT_EQ(b.poses.size(), truth.size());
  EXPECT_LT(a.summary.final_cost, 0.5 * a.summary.initial_cost);
  EXPECT_NEAR(a.summary.final_cost / b.summary.final_cost, 1.0, 1e-6);

  std::vector<Pose> pa, pb, pt;
  for (const auto& [id, pose] : truth) {
    pa.push_back(a.poses.at(id));
    pb.push_back(b.poses.at(id));
    pt.push_back(pose);
  }
  GroundTruthErrors between, to_truth, init_to_truth;
  RelativePoseErrors(pa, pb, &between);
  RelativePoseErrors(pa, pt, &to_truth);
  std::vector<Pose> pi;
  for (const auto& [id, pose] : truth) pi.push_back(initial.at(id));
  RelativePoseErrors(pi, pt, &init_to_truth);
  // 1e-5 deg: the solvers' stopping tolerances, four orders below the noise (0.1 deg here).
  EXPECT_LT(between.rel_rot_err_deg_max, 1e-5);
  EXPECT_LT(between.rel_dir_err_deg_max, 1e-5);
  // And the solve did its job: one Gauss-Newton step of the block from the perturbed poses
  // halves their error (0.41 -> 0.19 deg; the point-based optimum, 0.10, takes the
  // re-linearisation, which the pipeline tests judge).
  const std::map<uint32_t, Pose> pb_poses = testing::PointBasedBA(rec, initial);
  std::vector<Pose> ppb;
  for (const auto& [id, pose] : truth) ppb.push_back(pb_poses.at(id));
  GroundTruthErrors pb_to_truth;
  RelativePoseErrors(ppb, pt, &pb_to_truth);
  std::printf("  relative rotation error median: initial %.4f, one pointless solve %.4f, point-based %.4f deg\n",
              init_to_truth.rel_rot_err_deg_median, to_truth.rel_rot_err_deg_median,
              pb_to_truth.rel_rot_err_deg_median);
  EXPECT_LT(to_truth.rel_rot_err_deg_median, 0.55 * init_to_truth.rel_rot_err_deg_median);
}

// The embedded similarity iterations (GlobalBAOptions::embedded_similarity_iterations) change
// the path, not the optimum: the same final cost as the plain joint step, converged tight, in
// fewer iterations (the similarities' scales and the poses enter the residual bilinearly).
TEST(MotionBlockSolver, EmbeddedSimilarityIterationsReachTheSameOptimumSooner) {
  const RingMotions ring = MakeRingMotions();
  GlobalBAOptions embedded = GlobalBAOptions();
  embedded.solver.function_tolerance = 1e-12;
  embedded.solver.parameter_tolerance = 1e-14;
  embedded.solver.max_iterations = 100;
  embedded.solver.embedded_similarity_iterations = 1;
  GlobalBAOptions joint = embedded;
  joint.solver.embedded_similarity_iterations = 0;
  const GlobalBAResult a = PointlessGlobalBA(ring.initial, ring.motions, ring.hessians.hessians, embedded);
  const GlobalBAResult b = PointlessGlobalBA(ring.initial, ring.motions, ring.hessians.hessians, joint);
  std::printf("  iterations: embedded %d, joint %d; final cost %.9g vs %.9g\n", a.summary.iterations,
              b.summary.iterations, a.summary.final_cost, b.summary.final_cost);
  EXPECT_NEAR(a.summary.final_cost / b.summary.final_cost, 1.0, 1e-6);
  EXPECT_LT(a.summary.iterations, b.summary.iterations);
}

}  // namespace
}  // namespace pgba
