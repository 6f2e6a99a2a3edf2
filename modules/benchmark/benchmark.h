// The paper's evaluation (section 4): one shared initialisation, then every adjustment
// method from the same initial poses (pointless BA, point-based BA, Aver_BA), each judged by
// the same metrics (modules/evaluation: sigma, loop closure, ground-truth pose errors), with
// parameter counts, iterations, wall time of the adjustment alone and of its preparation,
// peak memory, and the sigma convergence curve (paper Figure 3). Optionally the outlier
// sweep of paper Figure 4: final sigma against the fraction of relative rotations replaced
// by random ones.
#pragma once

#include <map>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>
#include <vector>

#include "evaluation/evaluation.h"
#include "mapper/pointless_mapper.h"
#include "benchmark/baselines.h"
#include "mapper/pose_refinement.h"
#include "pgba/scene/reconstruction.h"

namespace pgba {

struct BenchmarkOptions {
  GlobalMapperOptions mapper;
  RefinementOptions refinement;
  EvaluationOptions evaluation;
  // Sigma after every iteration of every method (costs one triangulation per iteration,
  // outside the timed adjustment).
  bool convergence = true;
  // Outlier fractions of the sweep (empty: no sweep). Each runs its own initialisation
  // with that fraction of relative rotations corrupted, triplets kept whatever their
  // rotation misfit (so the adjustment, not the initialisation, faces the outliers), then
  // pointless BA and Aver_BA.
  std::vector<double> outlier_sweep;
  // Also run pointbased_split (pose_refinement.h): what the triplet structure costs.
  bool triplet_split = false;
  // Empty when valid, else one line naming the first field out of its valid range (the
  // ranges of io/option_ranges.cc) or breaking a rule between fields.
  std::string Check() const;
};

struct MethodOutcome {
  RefinementMethod method = RefinementMethod::kPointless;
  RefinementResult refinement;
  Reconstruction model;  // tracks triangulated with the refined poses
  EvaluationMetrics metrics;
  std::vector<double> convergence;  // sigma_rms per iteration (index 0: initial poses)
  // CPU time (all threads) of the adjustment and of the preparation it needs (the local
  // Hessians for the motion methods, the triangulation for the point-based BA).
  double cpu_seconds = 0.0;
};

struct SweepPoint {
  double fraction = 0.0;
  int pairs_corrupted = 0;
  int triplets_corrupted = 0;
  // Final sigma_rms per method (pointless, averaging); NaN where the run failed.
  double sigma_pointless = 0.0;
  double sigma_averaging = 0.0;
  // Images each method refined (a sigma over fewer images is not the same sigma).
  int images_pointless = 0;
  int images_averaging = 0;
  std::string error;  // why a run failed
};

struct BenchmarkResult {
  EvaluationMetrics init_metrics;  // the shared initial poses
  std::vector<MethodOutcome> methods;  // kAllRefinementMethods order, then pointbased_split
  std::vector<SweepPoint> sweep;
  // Methods not run, by name, with the reason (benchmark.json "skipped").
  std::map<std::string, std::string> skipped;
  // benchmark.json (docs/formats.md, "Reports"):
  // {"methods": {NAME: {"sigma_init", "sigma_final", "params", "iterations", "adjust_seconds",
  //   "prepare_seconds", "cpu_seconds", "peak_rss_mb", "loop_err_rms", "rot_err_deg_median", "convergence",
  //   ...}}, "init": {...}, "outlier_sweep": [...], "skipped": {NAME: reason}}
  nlohmann::json ToJson() const;
};

// Runs every method on `init` (the shared initialisation of `tracks`). `gt` and `loops` are
// optional (nullptr).
BenchmarkResult RunBenchmark(const Reconstruction& tracks, const GlobalMapperResult& init, const Reconstruction* gt,
                             const std::vector<LoopCorrespondence>* loops, const BenchmarkOptions& options);

// The paper's Table 1 (sigma_init, sigma_final, #params) and Table 2 (loop-closure error,
// #params) layouts, plus time, memory and ground-truth columns.
void PrintBenchmarkTables(const BenchmarkResult& result, std::ostream& out);

// Figure 3: sigma per iteration per method, log scale. Figure 4: final sigma against the
// outlier fraction, log scale.
std::string ConvergencePlot(const BenchmarkResult& result);
std::string OutlierSweepPlot(const BenchmarkResult& result);

}  // namespace pgba
