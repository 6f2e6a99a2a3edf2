// The paper's evaluation on small synthetic scenes (0.5 px noise, 2% outlier observations),
// from tracks through the real pipeline (pairs, triplets, averaging, local hessians): the
// pointless BA must reach the point-based BA's sigma with a fraction of its unknowns, Aver_BA
// is run and reported, and the benchmark's records (convergence curves, JSON keys, plots)
// are consistent with what the methods returned.
#include "benchmark/benchmark.h"

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "mapper/run_pipeline.h"
#include "report/svg_plot.h"
#include "synthetic/synthetic_scene.h"
#include "tests/support/acceptance_scene.h"

namespace pgba {
namespace {

struct Case {
  SyntheticScenario scenario;
  int images;
};

const MethodOutcome& Method(const BenchmarkResult& r, RefinementMethod m) {
  for (const MethodOutcome& o : r.methods)
    if (o.method == m) return o;
  throw std::runtime_error("method missing");
}

// The paper's method (triplets, attenuation, IRLS on the motions): configs/paper_triplets.json.
RefinementOptions PaperTriplets() {
  return LoadRunOptions(std::string(PGBA_SOURCE_DIR) + "/configs/paper_triplets.json").reconstruction.refinement;
}

BenchmarkResult RunScene(const Case& c, SyntheticScene* scene_out = nullptr) {
  const SyntheticScene scene = test::AcceptanceScene(c.scenario, c.images, /*seed=*/7);
  BenchmarkOptions options;
  options.refinement = PaperTriplets();
  Report report;
  const GlobalMapperResult init = RunGlobalMapper(scene.input, options.mapper, &report);
  BenchmarkResult r = RunBenchmark(scene.input, init, &scene.gt,
                                   scene.loop_pairs.empty() ? nullptr : &scene.loop_pairs, options);
  if (scene_out) *scene_out = scene;
  return r;
}

class BenchmarkOnScene : public ::testing::TestWithParam<Case> {};

TEST_P(BenchmarkOnScene, PaperTripletsReachPointBasedSigmaWithFarFewerUnknowns) {
  SyntheticScene scene;
  const BenchmarkResult r = RunScene(GetParam(), &scene);
  std::ostringstream table;
  PrintBenchmarkTables(r, table);
  std::cout << SyntheticScenarioName(GetParam().scenario) << table.str();

  const MethodOutcome& pl = Method(r, RefinementMethod::kPointless);
  const MethodOutcome& pb = Method(r, RefinementMethod::kPointBased);
  const MethodOutcome& av = Method(r, RefinementMethod::kAveraging);
  ASSERT_TRUE(pl.metrics.sigma.Computable());
  ASSERT_TRUE(pb.metrics.sigma.Computable());
  ASSERT_TRUE(av.metrics.sigma.Computable());
  EXPECT_EQ(pl.refinement.poses.size(), scene.gt.images.size());
  // Measured (seed 7): sigma 1.0091x (orbit), 1.0032x (aerial): the bar is 1.02x.
  EXPECT_LE(pl.metrics.sigma.rms, 1.02 * pb.metrics.sigma.rms);
  EXPECT_LE(4 * pl.refinement.num_params, pb.refinement.num_params);
  EXPECT_LT(pl.metrics.sigma.rms, r.init_metrics.sigma.rms);
  // Against the truth: the refinement does not lose what the initialisation had (measured
  // 0.51x of the initial rotation error on the orbit, 0.99x on the aerial block).
  ASSERT_TRUE(pl.metrics.ground_truth && pl.metrics.ground_truth->ok);
  EXPECT_LE(pl.metrics.ground_truth->rot_err_deg_median, 1.03 * r.init_metrics.ground_truth->rot_err_deg_median);

  // Records: one sigma per iteration plus the start, starting at sigma_init, ending at the
  // final sigma; the JSON carries the keys of docs/formats.md, "Reports".
  for (const MethodOutcome* m : {&pl, &pb, &av}) {
    ASSERT_EQ(m->convergence.size(), static_cast<size_t>(m->refinement.iterations) + 1)
        << RefinementMethodName(m->method);
    EXPECT_NEAR(m->convergence.front(), r.init_metrics.sigma.rms, 1e-9);
  }
  EXPECT_NEAR(pl.convergence.back(), pl.metrics.sigma.rms, 1e-9);
  const nlohmann::json j = r.ToJson();
  for (const char* name : {"pointless", "pointbased", "averaging"})
    for (const char* key : {"sigma_init", "sigma_final", "params", "iterations", "adjust_seconds", "prepare_seconds",
                            "peak_rss_mb", "rot_err_deg_median", "convergence"})
      EXPECT_TRUE(j["methods"][name].contains(key)) << name << "." << key;
  EXPECT_EQ(j["methods"]["pointless"]["params"].get<int>(), pl.refinement.num_params);
  // Wide-angle scenes: the local models agree with their consensus, no re-linearisation
  // (global_ba.h), so the adjustment time is that of a single pointless solve.
  const nlohmann::json& d = j["methods"]["pointless"]["details"]["method"];
  ASSERT_TRUE(d.contains("misfit_ratio_initial"));
  EXPECT_LT(d["misfit_ratio_initial"].get<double>(), 1.0);
  EXPECT_EQ(d["relinearizations"].get<int>(), 0);
  EXPECT_NE(table.str().find("no re-linearisation"), std::string::npos);
}

INSTANTIATE_TEST_SUITE_P(Scenarios, BenchmarkOnScene,
                         ::testing::Values(Case{SyntheticScenario::kOrbit, 70}, Case{SyntheticScenario::kAerial, 30}),
                         [](const auto& info) { return std::string(SyntheticScenarioName(info.param.scenario)); });

// The default method, whole-track motions (whole_track_motions.h), on the acceptance scenes:
// the poses are as accurate as the point-based BA's by the gauge-free metric (median and max
// relative rotation error over all image pairs), sigma equal, a quarter of the unknowns at
// most, and the re-linearised steps kept only where they lowered the robust cost. Measured
// here (seed 7; pointless / point-based): median 1.002 / 0.994 / 1.018, max 1.000 / 0.962 /
// 1.000, translation direction 1.000 / 0.984 / 1.017 (orbit / aerial / planar), sigma 1.0000;
// the bounds sit ~1% above the worst of them.
class DefaultOnScene : public ::testing::TestWithParam<Case> {};

TEST_P(DefaultOnScene, PosesAsAccurateAsPointBased) {
  const SyntheticScene scene = test::AcceptanceScene(GetParam().scenario, GetParam().images, /*seed=*/7);
  BenchmarkOptions options;
  options.convergence = false;
  Report report;
  const GlobalMapperResult init = RunGlobalMapper(scene.input, options.mapper, &report);
  const BenchmarkResult r = RunBenchmark(scene.input, init, &scene.gt, nullptr, options);
  std::ostringstream table;
  PrintBenchmarkTables(r, table);
  std::cout << SyntheticScenarioName(GetParam().scenario) << table.str();
  const MethodOutcome& pl = Method(r, RefinementMethod::kPointless);
  const MethodOutcome& pb = Method(r, RefinementMethod::kPointBased);
  // Every image the initialisation registered is refined (on the seed-7 planar video the
  // initialisation itself keeps 42 of 60).
  ASSERT_EQ(pl.refinement.poses.size(), init.init.poses.size());
  ASSERT_TRUE(pl.metrics.ground_truth && pb.metrics.ground_truth);
  const GroundTruthErrors& gl = *pl.metrics.ground_truth;
  const GroundTruthErrors& gb = *pb.metrics.ground_truth;
  ASSERT_GT(gl.num_pairs, 0u);
  EXPECT_LE(gl.rel_rot_err_deg_median, 1.03 * gb.rel_rot_err_deg_median);
  EXPECT_LE(gl.rel_rot_err_deg_max, 1.01 * gb.rel_rot_err_deg_max);
  EXPECT_LE(gl.rel_dir_err_deg_median, 1.03 * gb.rel_dir_err_deg_median);
  EXPECT_LE(pl.metrics.sigma.rms, 1.001 * pb.metrics.sigma.rms);
  EXPECT_LE(4 * pl.refinement.num_params, pb.refinement.num_params);
  const nlohmann::json j = r.ToJson();
  for (const char* key : {"rel_rot_err_deg_median", "rel_rot_err_deg_max", "rel_dir_err_deg_median"})
    EXPECT_TRUE(j["methods"]["pointless"].contains(key)) << key;
  EXPECT_EQ(j["methods"]["pointless"]["details"]["method"]["motion_kind"].get<std::string>(), "whole_tracks");
  EXPECT_GE(j["methods"]["pointless"]["details"]["method"]["relinearizations"].get<int>(), 1);
}

INSTANTIATE_TEST_SUITE_P(Scenarios, DefaultOnScene,
                         ::testing::Values(Case{SyntheticScenario::kOrbit, 70}, Case{SyntheticScenario::kAerial, 30},
                                           Case{SyntheticScenario::kPlanar, 60}),
                         [](const auto& info) { return std::string(SyntheticScenarioName(info.param.scenario)); });

// The long-focal loop (93 telephoto views, seed 1) with the default config: its initial poses
// are far from the triplets' relative rotations (TripletRotationMisfit ~1100 residuals against
// 1.7-8 on the scenes above), so the whole-track motions are linearised where the triplets'
// pointless BA puts the poses (mapper/linearization_start.h); from the initial poses they had
// ended 42x less accurate than the point-based BA. Measured here: misfit 1140.6 (threshold
// 300); with the start over 125 of the 260 triplets (local_motions.triplet_start_max_per_image
// 2) and three re-linearisations (converged; each re-triangulation started from the previous
// pass's points) relative rotation error median 1.001x, max 0.966x point-based, sigma 1.0003x
// (two passes, triangulated from scratch: 0.994x, 0.919x); the bounds sit ~1.5% above.
// Iterations of the pointless BA (all passes): 12 = 4 + 4 + 4; before the embedded similarity
// iterations and the carried trust region, 33 (the last solve crawled to its cap of 25 along the scale valley:
// motion_normal_equations.cc, OptimizeSimilarity).
TEST(DefaultOnLongFocal, TripletStartReachesPointBasedPoses) {
  const SyntheticScene scene = test::AcceptanceScene(SyntheticScenario::kLongFocal, 0, /*seed=*/1);
  BenchmarkOptions options;
  options.convergence = false;
  Report report;
  const GlobalMapperResult init = RunGlobalMapper(scene.input, options.mapper, &report);
  const BenchmarkResult r = RunBenchmark(scene.input, init, &scene.gt, nullptr, options);
  std::ostringstream table;
  PrintBenchmarkTables(r, table);
  std::cout << "longfocal" << table.str();
  const MethodOutcome& pl = Method(r, RefinementMethod::kPointless);
  const MethodOutcome& pb = Method(r, RefinementMethod::kPointBased);
  const nlohmann::json d = r.ToJson()["methods"]["pointless"]["details"]["method"];
  std::printf("  triplet rotation misfit %.1f, start %d\n", d["triplet_rotation_misfit"].get<double>(),
              d["triplet_start"].get<bool>());
  EXPECT_TRUE(d["triplet_start"].get<bool>());
  EXPECT_GT(d["triplet_rotation_misfit"].get<double>(), options.refinement.local_motions.triplet_start_misfit);
  ASSERT_EQ(pl.refinement.poses.size(), init.init.poses.size());
  ASSERT_TRUE(pl.metrics.ground_truth && pb.metrics.ground_truth);
  const GroundTruthErrors& gl = *pl.metrics.ground_truth;
  const GroundTruthErrors& gb = *pb.metrics.ground_truth;
  EXPECT_LE(gl.rel_rot_err_deg_median, 1.016 * gb.rel_rot_err_deg_median);
  EXPECT_LE(gl.rel_rot_err_deg_max, 0.981 * gb.rel_rot_err_deg_max);
  EXPECT_LE(pl.metrics.sigma.rms, 1.001 * pb.metrics.sigma.rms);
  EXPECT_LE(pl.refinement.iterations, 14);
  EXPECT_LE(4 * pl.refinement.num_params, pb.refinement.num_params);
}

TEST(SvgPlot, LogScaleSkipsNonPositiveValuesAndNamesEverySeries) {
  PlotOptions o;
  o.log_y = true;
  o.title = "t<1>";
  const std::string svg = LinePlotSvg({{"a", {0, 1, 2}, {1.0, 0.5, -1.0}}, {"b & c", {0, 1}, {NAN, 2.0}}}, o);
  EXPECT_EQ(svg.rfind("<svg", 0), 0u);
  EXPECT_NE(svg.find("</svg>"), std::string::npos);
  EXPECT_NE(svg.find("t&lt;1&gt;"), std::string::npos);
  EXPECT_NE(svg.find("b &amp; c"), std::string::npos);
  // Series a: two drawable points -> a polyline; series b: one -> a marker only.
  size_t polylines = 0, circles = 0;
  for (size_t p = svg.find("<polyline"); p != std::string::npos; p = svg.find("<polyline", p + 1)) ++polylines;
  for (size_t p = svg.find("<circle"); p != std::string::npos; p = svg.find("<circle", p + 1)) ++circles;
  EXPECT_EQ(polylines, 1u);
  EXPECT_EQ(circles, 3u);
}


// The long-focal loop of docs/benchmarks.md (93 telephoto views, seed 1; tracks over 10-30 of
// them) with the paper's weighting over motions of 7 views (local_motions.kind neighbours; the
// default's whole-track motions do better still) against the paper's triplets, on one
// initialisation: the motions meet the loop bar there (loop 1.30x point-based, sigma 1.005:
// Table 1 of docs/benchmarks.md) and cut the triplets' rotation error to a third.
TEST(LongFocalMotions, SevenViewMotionsMeetTheLoopBar) {
  const SyntheticScene scene = test::AcceptanceScene(SyntheticScenario::kLongFocal, 0, /*seed=*/1);
  BenchmarkOptions options;
  options.convergence = false;
  Report report;
  const GlobalMapperResult init = RunGlobalMapper(scene.input, options.mapper, &report);
  options.refinement = PaperTriplets();
  options.refinement.local_motions.kind = MotionKind::kNeighbours;
  options.refinement.local_motions.views = 7;
  const BenchmarkResult motions = RunBenchmark(scene.input, init, &scene.gt, &scene.loop_pairs, options);
  options.refinement.local_motions.kind = MotionKind::kTriplets;
  const BenchmarkResult triplets = RunBenchmark(scene.input, init, &scene.gt, &scene.loop_pairs, options);

  const MethodOutcome& pl = Method(motions, RefinementMethod::kPointless);
  const MethodOutcome& pb = Method(motions, RefinementMethod::kPointBased);
  const MethodOutcome& tr = Method(triplets, RefinementMethod::kPointless);
  ASSERT_TRUE(pl.metrics.loop && pb.metrics.loop && tr.metrics.loop);
  std::printf("  sigma: motions %.4f, triplets %.4f, point-based %.4f; rotation error median %.4f, %.4f, %.4f deg; "
              "loop %.3f, %.3f, %.3f px\n",
              pl.metrics.sigma.rms, tr.metrics.sigma.rms, pb.metrics.sigma.rms,
              pl.metrics.ground_truth->rot_err_deg_median, tr.metrics.ground_truth->rot_err_deg_median,
              pb.metrics.ground_truth->rot_err_deg_median, pl.metrics.loop->rms, tr.metrics.loop->rms,
              pb.metrics.loop->rms);
  EXPECT_EQ(pl.refinement.poses.size(), scene.gt.images.size());
  EXPECT_LE(pl.metrics.sigma.rms, 1.01 * pb.metrics.sigma.rms);
  EXPECT_LE(4 * pl.refinement.num_params, pb.refinement.num_params);
  EXPECT_LE(pl.metrics.loop->rms, 1.4 * pb.metrics.loop->rms);
  EXPECT_LE(pl.metrics.ground_truth->rot_err_deg_median, 0.5 * tr.metrics.ground_truth->rot_err_deg_median);
  EXPECT_EQ(motions.ToJson()["methods"]["pointless"]["details"]["method"]["motion_kind"].get<std::string>(),
            "neighbours");
}

// The pointless BA approximates, by one quadratic per triplet, the sum of the triplets' own
// point-based costs (each triplet with its private points). A point-based BA over exactly
// those tracks (pointbased_split) must then land where the pointless BA lands: the local
// hessians lose nothing measurable. What both lose against the full point-based BA is the
// triplet structure (on this orbit: rotation errors ~1.8x), not the approximation.
TEST(TripletSplitBaseline, PointlessMatchesTheObjectiveItApproximates) {
  const SyntheticScene scene = test::AcceptanceScene(SyntheticScenario::kOrbit, 40, /*seed=*/7);
  BenchmarkOptions options;
  options.refinement = PaperTriplets();
  options.convergence = false;
  options.triplet_split = true;
  Report report;
  const GlobalMapperResult init = RunGlobalMapper(scene.input, options.mapper, &report);
  const BenchmarkResult r = RunBenchmark(scene.input, init, &scene.gt, nullptr, options);
  const MethodOutcome& pl = Method(r, RefinementMethod::kPointless);
  const MethodOutcome& pb = Method(r, RefinementMethod::kPointBased);
  const MethodOutcome& split = Method(r, RefinementMethod::kPointBasedSplit);
  std::printf("  sigma: pointless %.4f, split %.4f, point-based %.4f; rotation error median: %.4f, %.4f, %.4f deg\n",
              pl.metrics.sigma.rms, split.metrics.sigma.rms, pb.metrics.sigma.rms,
              pl.metrics.ground_truth->rot_err_deg_median, split.metrics.ground_truth->rot_err_deg_median,
              pb.metrics.ground_truth->rot_err_deg_median);
  EXPECT_EQ(split.refinement.poses.size(), scene.gt.images.size());
  EXPECT_NEAR(pl.metrics.sigma.rms / split.metrics.sigma.rms, 1.0, 0.01);
  EXPECT_GE(split.metrics.sigma.rms, 0.999 * pb.metrics.sigma.rms);
  EXPECT_NEAR(pl.metrics.ground_truth->rot_err_deg_median / split.metrics.ground_truth->rot_err_deg_median, 1.0, 0.25);
  EXPECT_TRUE(r.ToJson()["methods"].contains("pointbased_split"));
}

// Paper Figure 4: relative motions corrupted by random rotations (20% of the pairs and of the
// triplets, in what the initialisation averages and in the motions x0 the adjustment
// averages). The pointless BA's IRLS must shrug them off: every image kept and sigma within
// 2% of the clean run's, on the same scene (`pgba benchmark --outlier-sweep` on the seed-1 orbit:
// +0.4% at 22%, Aver_BA +3%).
TEST(OutlierSweep, PointlessBAIsRobustToOutlierMotions) {
  const SyntheticScene scene = test::AcceptanceScene(SyntheticScenario::kOrbit, 70, /*seed=*/7);
  BenchmarkOptions options;
  options.refinement = PaperTriplets();
  options.outlier_sweep = {0.0, 0.2};
  Report report;
  const GlobalMapperResult init = RunGlobalMapper(scene.input, options.mapper, &report);
  const BenchmarkResult r = RunBenchmark(scene.input, init, &scene.gt, nullptr, options);
  ASSERT_EQ(r.sweep.size(), 2u);
  const SweepPoint& clean = r.sweep[0];
  const SweepPoint& corrupted = r.sweep[1];
  std::printf("  clean: sigma %.4f (%d images); 20%%: %d pairs, %d triplets corrupted, sigma %.4f (%d images); "
              "Aver_BA %.4f -> %.4f\n",
              clean.sigma_pointless, clean.images_pointless, corrupted.pairs_corrupted, corrupted.triplets_corrupted,
              corrupted.sigma_pointless, corrupted.images_pointless, clean.sigma_averaging, corrupted.sigma_averaging);
  EXPECT_EQ(clean.triplets_corrupted, 0);
  EXPECT_GT(corrupted.triplets_corrupted, 0);
  EXPECT_GT(corrupted.pairs_corrupted, 0);
  EXPECT_EQ(clean.images_pointless, 70);
  EXPECT_EQ(corrupted.images_pointless, 70);
  EXPECT_LE(corrupted.sigma_pointless, 1.02 * clean.sigma_pointless);
  const nlohmann::json j = r.ToJson();
  EXPECT_EQ(j["outlier_sweep"][1]["images_pointless"].get<int>(), 70);
}

}  // namespace
}  // namespace pgba
