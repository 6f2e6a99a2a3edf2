// PointlessMapper::Solve, the pipeline of steps 1-8, on a small synthetic orbit (0.5 px noise,
// 2% outlier observations): the poses against the scene's truth, and the steps' contract
// (a step whose artefact the state holds is not run again, skip_refinement stops after the
// initial solution, invalid options are refused before any work).
#include <gtest/gtest.h>

#include <cstdio>
#include <stdexcept>

#include "benchmark/baselines.h"
#include "evaluation/ground_truth.h"
#include "mapper/pointless_mapper.h"
#include "synthetic/synthetic_scene.h"

namespace pgba {
namespace {

SyntheticScene Orbit() {
  SyntheticOptions so;
  so.scenario = SyntheticScenario::kOrbit;
  so.seed = 3;
  so.num_images = 40;
  so.noise_px = 0.5;
  so.outlier_fraction = 0.02;
  return GenerateSyntheticScene(so);
}

double MedianRelativeRotationDeg(const std::map<uint32_t, Pose>& poses, const Reconstruction& gt) {
  std::vector<Pose> est, truth;
  for (const auto& [id, pose] : poses) {
    est.push_back(pose);
    truth.push_back(gt.images.at(id).pose);
  }
  GroundTruthErrors e;
  RelativePoseErrors(est, truth, &e);
  return e.rel_rot_err_deg_median;
}

std::vector<std::string> StageNames(const Report& report) {
  std::vector<std::string> names;
  for (const auto& [name, stage] : report.json().at("stages").items()) names.push_back(name);
  return names;
}

TEST(PointlessMapper, SolvesEveryStepToTheTruthAndSkipsTheStepsItsStateHolds) {
  const SyntheticScene scene = Orbit();
  const PointlessMapper mapper(PointlessMapperOptions{});
  Report full_report;
  const PointlessMapperResult full = mapper.Solve(scene.input, &full_report);
  ASSERT_EQ(full.refined.poses.size(), scene.gt.images.size());
  EXPECT_EQ(full.model.points3D.size(), full_report.json().at("stages").at("triangulation").at("points").get<size_t>());
  // Gauge-free: relative rotations over all pairs against the truth's, against the
  // point-based BA from the same initial poses: the converged pointless BA is the point-based
  // optimum.
  const RefinementResult point_based = RefinePoses(RefinementMethod::kPointBased, scene.input, full.initial.init.poses,
                                                   {}, nullptr, mapper.options().refinement);
  const double pointless = MedianRelativeRotationDeg(full.refined.poses, scene.gt);
  const double reference = MedianRelativeRotationDeg(point_based.poses, scene.gt);
  const double initial = MedianRelativeRotationDeg(full.initial.init.poses, scene.gt);
  std::printf("relative rotation error median: initial %.4f, pointless %.4f, point-based %.4f deg\n", initial,
              pointless, reference);
  EXPECT_LT(pointless, 1.03 * reference);

  // The same Solve from the state after step 5: steps 1-5 are not run again (no such stage in
  // the report) and steps 6-9 give the same poses to the bit.
  PointlessMapperResult state;
  state.initial = full.initial;
  state.hessians = full.hessians;
  Report resumed_report;
  const PointlessMapperResult resumed = mapper.Solve(scene.input, &resumed_report, state);
  EXPECT_EQ(StageNames(resumed_report), (std::vector<std::string>{"global_ba", "triangulation", "verification"}));
  ASSERT_EQ(resumed.refined.poses.size(), full.refined.poses.size());
  for (const auto& [id, pose] : full.refined.poses) {
    EXPECT_EQ(resumed.refined.poses.at(id).q().coeffs(), pose.q().coeffs()) << "image " << id;
    EXPECT_EQ(resumed.refined.poses.at(id).t(), pose.t()) << "image " << id;
  }
}

TEST(PointlessMapper, SkipRefinementStopsAfterTheInitialSolution) {
  const SyntheticScene scene = Orbit();
  PointlessMapperOptions options;
  options.skip_refinement = true;
  Report report;
  const PointlessMapperResult r = PointlessMapper(options).Solve(scene.input, &report);
  EXPECT_TRUE(r.initial.init.success);
  EXPECT_EQ(r.initial.init.poses.size(), scene.gt.images.size());
  EXPECT_TRUE(r.hessians.motions.empty());
  EXPECT_TRUE(r.refined.poses.empty());
  EXPECT_EQ(StageNames(report), (std::vector<std::string>{"global_init", "pairs", "triplets"}));
}

TEST(PointlessMapper, InvalidOptionsAreRefusedNamingTheKey) {
  PointlessMapperOptions options;
  options.convergence.max_tracks = -1;
  try {
    PointlessMapper mapper(options);
    FAIL() << "accepted an invalid option";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("convergence.max_tracks"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace pgba
