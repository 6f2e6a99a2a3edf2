// The point-based bundle adjuster (optim/bundle_adjuster) started from the true poses of
// the planar synthetic scene (video along a flat wall, 60 frames, 0.5 px noise, 2% outliers)
// in the benchmark baseline's configuration (all images, ChooseGauge, filter-and-refine at
// 4 px): it should converge (Ceres CONVERGENCE, not the iteration budget) in a modest number
// of iterations to a sigma close to the truth's. Huber (the default loss) does only once the
// gross outliers are gone; with them left in it settles at ~0.62 px and ~0.9 deg: the reason
// the benchmark's baseline runs its first pass with Cauchy (PointBasedOptions, tested in
// tests/benchmark/baselines_test.cc).
#include "pgba/optim/bundle_adjuster.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>

#include "evaluation/ground_truth.h"
#include "evaluation/sigma.h"
#include "pgba/geometry/rotation.h"
#include "pgba/scene/triangulate_model.h"
#include "synthetic/synthetic_scene.h"
#include "tests/support/acceptance_scene.h"

namespace pgba {
namespace {

std::map<uint32_t, Pose> PosesOf(const Reconstruction& rec) {
  std::map<uint32_t, Pose> poses;
  for (const auto& [id, im] : rec.images) poses[id] = im.pose;
  return poses;
}

SyntheticScene Generate(SyntheticScenario scenario) { return test::AcceptanceScene(scenario, 0, /*seed=*/1); }

struct Outcome {
  bool converged = true;
  int iterations = 0;
  double sigma = 0.0;
  double rot_err_median = 0.0;
  double rot_err_max = 0.0;
};

// Point-based BA of every image from `start` (poses), filter-and-refine, as the benchmark.
Outcome RunPointBased(const SyntheticScene& s, const std::map<uint32_t, Pose>& start, const std::string& loss,
                      bool prefilter = false) {
  Reconstruction model = TriangulateModel(s.input, start);
  BundleAdjustmentProblem problem;
  ChooseGauge(model, &problem);
  BundleAdjusterOptions o;
  o.loss.type = ParseLossType(loss);
  o.solver.log_progress = std::getenv("PGBA_BA_LOG") != nullptr;  // Ceres progress, for diagnosis
  Outcome out;
  if (prefilter) std::printf("  gross outliers removed before the first pass: %zu\n", FilterObservations(4.0, &model));
  for (int pass = 0; pass < 2; ++pass) {
    const BundleAdjustmentSummary sum = BundleAdjust(problem, o, &model);
    EXPECT_TRUE(sum.usable) << sum.message;
    out.converged = out.converged && sum.converged;
    out.iterations += sum.iterations;
    std::printf("  %s pass %d: %d iterations, %s\n", loss.c_str(), pass, sum.iterations, sum.message.c_str());
    if (pass == 0 && FilterObservations(4.0, &model) == 0) break;
  }
  out.sigma = EvaluateSigma(s.input, PosesOf(model)).rms;
  const GroundTruthErrors e = CompareToGroundTruth(model, s.gt);
  EXPECT_TRUE(e.ok);
  out.rot_err_median = e.rot_err_deg_median;
  out.rot_err_max = e.rot_err_deg_max;
  std::printf("  %s: sigma %.4f px, rotation error median %.4f max %.4f deg\n", loss.c_str(), out.sigma,
              out.rot_err_median, out.rot_err_max);
  return out;
}

// Reference: the gross outliers (> 4 px at the truth) removed before the first pass. Huber
// at 1 px then costs only a little efficiency: it converges in a few iterations to the sigma
// of the plain least-squares solution (about the truth's).
TEST(BundleAdjuster, PlanarHuberWithoutGrossOutliersConverges) {
  const SyntheticScene s = Generate(SyntheticScenario::kPlanar);
  const std::map<uint32_t, Pose> truth = PosesOf(s.gt);
  const double sigma_truth = EvaluateSigma(s.input, truth).rms;
  std::printf("  truth: sigma %.4f px\n", sigma_truth);
  const Outcome plain = RunPointBased(s, truth, "trivial", /*prefilter=*/true);
  const Outcome huber = RunPointBased(s, truth, "huber", /*prefilter=*/true);
  EXPECT_TRUE(plain.converged);
  EXPECT_TRUE(huber.converged);
  EXPECT_LE(huber.iterations, 20);
  EXPECT_LT(huber.sigma, plain.sigma + 0.005);
  EXPECT_LT(huber.sigma, sigma_truth + 0.01);
  EXPECT_LT(huber.rot_err_max, plain.rot_err_max + 0.05);
}

// The diagnosis: a redescending loss at the same 1 px scale, with the 2% gross outliers
// (uniform in the image, hundreds of px) left in, also converges in a few iterations to
// that solution; the trouble of Huber below is its non-vanishing influence on them.
TEST(BundleAdjuster, PlanarCauchyWithGrossOutliersConverges) {
  const SyntheticScene s = Generate(SyntheticScenario::kPlanar);
  const std::map<uint32_t, Pose> truth = PosesOf(s.gt);
  const double sigma_truth = EvaluateSigma(s.input, truth).rms;
  const Outcome cauchy = RunPointBased(s, truth, "cauchy");
  EXPECT_TRUE(cauchy.converged);
  EXPECT_LE(cauchy.iterations, 20);
  EXPECT_LT(cauchy.sigma, sigma_truth + 0.01);
}

}  // namespace
}  // namespace pgba
