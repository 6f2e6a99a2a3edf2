#include "benchmark/benchmark.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <set>

#include "pgba/io/option_ranges.h"
#include "report/svg_plot.h"
#include "averaging/outlier_injection.h"
#include "pgba/io/report.h"
#include "pgba/util/cpu_time.h"
#include "pgba/util/text_format.h"
#include "pgba/scene/triangulate_model.h"
#include "pgba/util/error.h"
#include "pgba/util/logging.h"

namespace pgba {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double SigmaOrNaN(const SigmaResult& s) { return s.Computable() ? s.rms : kNaN; }

// Aver_BA (the paper's baseline) averages relative motions that their own local BAs solved,
// the triplets of configs/paper_triplets.json. Whole-track motions are not solved locally
// (local_hessian.max_iterations 0: their x0 are the linearisation poses), so averaging them
// hands back those poses: a row that would read as a result. It is not run then.
constexpr const char* kAveragingNeedsSolvedMotions =
    "Aver_BA needs motions solved by their own local BAs (whole-track motions are not): run with --config "
    "configs/paper_triplets.json";

bool AveragingApplies(const BenchmarkOptions& options) {
  return options.refinement.local_motions.kind != MotionKind::kWholeTracks;
}

MethodOutcome RunMethod(RefinementMethod method, const Reconstruction& tracks, const GlobalMapperResult& init,
                        const PreparedHessians* hessians, const Reconstruction* gt,
                        const std::vector<LoopCorrespondence>* loops, const BenchmarkOptions& options,
                        double hessians_cpu_seconds) {
  MethodOutcome m;
  m.method = method;
  const CpuTimer cpu;
  m.refinement =
      RefinePoses(method, tracks, init.init.poses, init.init.triplets, hessians, options.refinement, options.convergence);
  m.cpu_seconds = cpu.Seconds();
  if (method != RefinementMethod::kPointBased && method != RefinementMethod::kPointBasedSplit)
    m.cpu_seconds += hessians_cpu_seconds;
  // A self-calibrating method is triangulated, evaluated and written with the cameras it
  // estimated (its sigma through the input cameras would measure the prior's error).
  const Reconstruction refined =
      m.refinement.cameras.empty() ? Reconstruction() : TracksWithCameras(tracks, m.refinement.cameras);
  const Reconstruction& with_cameras = m.refinement.cameras.empty() ? tracks : refined;
  m.model = TriangulateModel(with_cameras, m.refinement.poses);
  m.metrics = Evaluate(m.model, with_cameras, gt, loops, options.evaluation);
  for (const auto& poses : m.refinement.history)
    m.convergence.push_back(SigmaOrNaN(EvaluateSigma(with_cameras, poses, options.evaluation.sigma)));
  m.refinement.history.clear();  // poses per iteration are not needed past the curve
  return m;
}

// Gives `fraction` of the relative motions that the global BA averages a random rotation: one
// view's x0 (LocalHessian::local_poses) per chosen triplet, its h kept, as if the relative
// motion had been estimated wrong and its local BA had not noticed (a triplet whose local
// poses are corrupted before its local BA is rejected there by its own points). Returns the
// number corrupted. Only when the motions are the triplets (local_motions.views = 3): N-view
// motions are built from the initial poses, which carry the initialisation's outliers already.
int CorruptMotions(double fraction, uint64_t seed, const std::vector<LocalMotion>& triplets,
                   PreparedHessians* prepared) {
  std::vector<LocalHessian>* hessians = &prepared->result.hessians;
  if (prepared->motions.size() != triplets.size() ||
      std::any_of(prepared->motions.begin(), prepared->motions.end(),
                  [](const LocalMotion& m) { return m.num_views() != 3; })) {
    PGBA_LOG_WARN << "outlier sweep: the motions are not the triplets; only the initialisation is corrupted";
    return 0;
  }
  std::vector<LocalMotion> motions = triplets;
  OutlierInjectionOptions o;
  o.fraction = fraction;
  o.target = OutlierTarget::kTriplets;
  o.seed = seed;
  const OutlierInjectionResult injected = InjectRotationOutliers(o, nullptr, &motions);
  const std::set<int> chosen(injected.triplets.begin(), injected.triplets.end());
  for (LocalHessian& h : *hessians)
    if (chosen.count(h.motion_index))
      h.local_poses.assign(motions[h.motion_index].local_poses.begin(), motions[h.motion_index].local_poses.end());
  return static_cast<int>(injected.triplets.size());
}

// Paper Figure 4: final sigma of pointless BA and Aver_BA when `fraction` of the relative
// rotations are outliers, both in what the initialisation averages (the pairs and the
// triplets' relative rotations, outlier_injection.h) and in the motions the adjustment
// averages (CorruptMotions). The initialisation's triplet filtering is off: the adjustment
// faces every corrupted motion.
SweepPoint RunSweepPoint(const Reconstruction& input_tracks, double fraction, const BenchmarkOptions& options) {
  SweepPoint p;
  p.fraction = fraction;
  p.sigma_pointless = p.sigma_averaging = kNaN;
  GlobalMapperOptions mapper = options.mapper;
  mapper.rotation_outliers.fraction = fraction;
  mapper.rotation_outliers.triplet_corruption = TripletCorruption::kRelativeRotations;
  mapper.global_init.max_triplet_rotation_error_deg = 0.0;
  try {
    Report scratch;
    const GlobalMapperResult init = RunGlobalMapper(input_tracks, mapper, &scratch);
    const Reconstruction tracks = TracksWithCameras(input_tracks, init.cameras);  // the mapper's cameras
    p.pairs_corrupted = static_cast<int>(init.outliers_injected.pairs.size());
    PreparedHessians h = PrepareLocalHessians(tracks, init.init.poses, init.init.triplets, options.refinement);
    p.triplets_corrupted = CorruptMotions(fraction, mapper.rotation_outliers.seed, init.init.triplets, &h);
    for (RefinementMethod method : {RefinementMethod::kPointless, RefinementMethod::kAveraging}) {
      if (method == RefinementMethod::kAveraging && !AveragingApplies(options)) continue;  // NaN, 0 images
      const RefinementResult r =
          RefinePoses(method, tracks, init.init.poses, init.init.triplets, &h, options.refinement, false);
      const double sigma = SigmaOrNaN(EvaluateSigma(tracks, r.poses, options.evaluation.sigma));
      const bool pointless = method == RefinementMethod::kPointless;
      (pointless ? p.sigma_pointless : p.sigma_averaging) = sigma;
      (pointless ? p.images_pointless : p.images_averaging) = static_cast<int>(r.poses.size());
    }
  } catch (const std::exception& e) {
    p.error = e.what();
    PGBA_LOG_WARN << "outlier sweep at " << fraction << ": " << e.what();
  }
  return p;
}

}  // namespace

BenchmarkResult RunBenchmark(const Reconstruction& tracks, const GlobalMapperResult& init, const Reconstruction* gt,
                             const std::vector<LoopCorrespondence>* loops, const BenchmarkOptions& options) {
  BenchmarkResult result;
  result.init_metrics = Evaluate(TriangulateModel(tracks, init.init.poses), tracks, gt, loops, options.evaluation);
  const CpuTimer cpu;
  const PreparedHessians hessians = PrepareLocalHessians(tracks, init.init.poses, init.init.triplets, options.refinement);
  const double hessians_cpu = cpu.Seconds();
  for (RefinementMethod method : kAllRefinementMethods) {
    if (method == RefinementMethod::kAveraging && !AveragingApplies(options)) {
      result.skipped[RefinementMethodName(method)] = kAveragingNeedsSolvedMotions;
      continue;
    }
    result.methods.push_back(RunMethod(method, tracks, init, &hessians, gt, loops, options, hessians_cpu));
  }
  if (options.triplet_split)
    result.methods.push_back(
        RunMethod(RefinementMethod::kPointBasedSplit, tracks, init, &hessians, gt, loops, options, hessians_cpu));
  for (double f : options.outlier_sweep) result.sweep.push_back(RunSweepPoint(tracks, f, options));
  return result;
}

nlohmann::json BenchmarkResult::ToJson() const {
  nlohmann::json j;
  j["init"] = init_metrics.ToJson();
  const double sigma_init = SigmaOrNaN(init_metrics.sigma);
  for (const MethodOutcome& m : methods) {
    nlohmann::json e = m.metrics.ToJson();
    const RefinementResult& r = m.refinement;
    e["sigma_init"] = NumberOrNull(sigma_init);
    e["sigma_final"] = NumberOrNull(SigmaOrNaN(m.metrics.sigma));
    e["params"] = r.num_params;
    e["iterations"] = r.iterations;
    e["adjust_seconds"] = r.adjust_seconds;
    e["prepare_seconds"] = r.prepare_seconds;
    e["cpu_seconds"] = m.cpu_seconds;
    e["peak_rss_mb"] = r.peak_rss_mb;
    e["images_excluded"] = r.excluded_images.size();
    if (!r.intrinsics.empty()) e["intrinsics"] = r.intrinsics;  // per camera: initial, final, stddev
    e["convergence"] = nlohmann::json::array();
    for (double s : m.convergence) e["convergence"].push_back(NumberOrNull(s));
    e["details"]["method"] = r.details;
    j["methods"][RefinementMethodName(m.method)] = e;
  }
  for (const auto& [name, reason] : skipped) j["skipped"][name] = reason;
  if (!sweep.empty()) {
    j["outlier_sweep"] = nlohmann::json::array();
    for (const SweepPoint& p : sweep) {
      nlohmann::json e = {{"fraction", p.fraction},
                          {"pairs_corrupted", p.pairs_corrupted},
                          {"triplets_corrupted", p.triplets_corrupted},
                          {"sigma_final_pointless", NumberOrNull(p.sigma_pointless)},
                          {"sigma_final_averaging", NumberOrNull(p.sigma_averaging)},
                          {"images_pointless", p.images_pointless},
                          {"images_averaging", p.images_averaging}};
      if (!p.error.empty()) e["error"] = p.error;
      j["outlier_sweep"].push_back(e);
    }
  }
  return j;
}

namespace {

const char* DisplayName(RefinementMethod m) {
  switch (m) {
    case RefinementMethod::kPointless:
      return "Ours_BA (pointless)";
    case RefinementMethod::kPointBased:
      return "Point-based BA";
    case RefinementMethod::kAveraging:
      return "Aver_BA";
    case RefinementMethod::kPointBasedSplit:
      return "Point-based, split";
  }
  return "?";
}

}  // namespace

void PrintBenchmarkTables(const BenchmarkResult& result, std::ostream& out) {
  const double sigma_init = SigmaOrNaN(result.init_metrics.sigma);
  char line[512];
  out << "\nTable 1 (reprojection errors, px; params = unknowns of the adjustment)\n";
  std::snprintf(line, sizeof(line), "%-22s %10s %10s %10s %6s %11s %11s %9s\n", "method", "sigma_init",
                "sigma_final", "params", "iters", "adjust_s", "prepare_s", "rss_MB");
  out << line;
  for (const MethodOutcome& m : result.methods) {
    const RefinementResult& r = m.refinement;
    std::snprintf(line, sizeof(line), "%-22s %10s %10s %10d %6d %11.4f %11.4f %9.1f\n", DisplayName(m.method),
                  FormatNumber("%.4f", sigma_init).c_str(), FormatNumber("%.4f", SigmaOrNaN(m.metrics.sigma)).c_str(), r.num_params,
                  r.iterations, r.adjust_seconds, r.prepare_seconds, r.peak_rss_mb);
    out << line;
  }
  for (const auto& [name, reason] : result.skipped) out << "(" << name << " not run: " << reason << ")\n";
  const bool has_loop = result.init_metrics.loop && result.init_metrics.loop->Computable();
  if (has_loop) {
    out << "\nTable 2 (loop-closure error on withheld correspondences, px)\n";
    std::snprintf(line, sizeof(line), "%-22s %12s %12s %10s\n", "method", "err_loop_rms", "err_loop_med", "params");
    out << line;
    std::snprintf(line, sizeof(line), "%-22s %12s %12s %10s\n", "initial poses",
                  FormatNumber("%.3f", result.init_metrics.loop->rms).c_str(),
                  FormatNumber("%.3f", result.init_metrics.loop->median).c_str(), "-");
    out << line;
    for (const MethodOutcome& m : result.methods) {
      const bool ok = m.metrics.loop && m.metrics.loop->Computable();
      std::snprintf(line, sizeof(line), "%-22s %12s %12s %10d\n", DisplayName(m.method),
                    FormatNumber("%.3f", ok ? m.metrics.loop->rms : kNaN).c_str(),
                    FormatNumber("%.3f", ok ? m.metrics.loop->median : kNaN).c_str(), m.refinement.num_params);
      out << line;
    }
  }
  if (result.init_metrics.ground_truth && result.init_metrics.ground_truth->num_pairs > 0) {
    out << "\nGround truth: gauge-free errors over all image pairs (rel_*), and after a similarity alignment of "
           "the centres\n";
    std::snprintf(line, sizeof(line), "%-22s %12s %12s %12s %12s %12s %14s %10s\n", "method", "rel_rot_med",
                  "rel_rot_max", "rel_dir_med", "rot_med_deg", "rot_max_deg", "centre_med_rel", "images");
    out << line;
    auto row = [&](const char* name, const EvaluationMetrics& e) {
      const bool pairs = e.ground_truth && e.ground_truth->num_pairs > 0;
      const bool ok = e.ground_truth && e.ground_truth->ok;
      std::snprintf(line, sizeof(line), "%-22s %12s %12s %12s %12s %12s %14s %4zu / %-4zu\n", name,
                    FormatNumber("%.5f", pairs ? e.ground_truth->rel_rot_err_deg_median : kNaN).c_str(),
                    FormatNumber("%.5f", pairs ? e.ground_truth->rel_rot_err_deg_max : kNaN).c_str(),
                    FormatNumber("%.5f", pairs ? e.ground_truth->rel_dir_err_deg_median : kNaN).c_str(),
                    FormatNumber("%.5f", ok ? e.ground_truth->rot_err_deg_median : kNaN).c_str(),
                    FormatNumber("%.5f", ok ? e.ground_truth->rot_err_deg_max : kNaN).c_str(),
                    FormatNumber("%.3e", ok ? e.ground_truth->center_err_rel_median : kNaN).c_str(), e.images_registered,
                    e.images_input);
      out << line;
    };
    row("initial poses", result.init_metrics);
    for (const MethodOutcome& m : result.methods) row(DisplayName(m.method), m.metrics);
  }
  const MethodOutcome* pl = nullptr;
  const MethodOutcome* pb = nullptr;
  for (const MethodOutcome& m : result.methods) {
    if (m.method == RefinementMethod::kPointless) pl = &m;
    if (m.method == RefinementMethod::kPointBased) pb = &m;
  }
  if (pl && pb) {
    const double sp = SigmaOrNaN(pl->metrics.sigma), sb = SigmaOrNaN(pb->metrics.sigma);
    out << "\npointless / point-based: sigma " << FormatNumber("%.4f", sp / sb) << ", params "
        << FormatNumber("%.3f", static_cast<double>(pl->refinement.num_params) / pb->refinement.num_params)
        << ", adjustment time " << FormatNumber("%.3f", pl->refinement.adjust_seconds / pb->refinement.adjust_seconds)
        << ", adjustment + preparation time "
        << FormatNumber("%.3f", (pl->refinement.adjust_seconds + pl->refinement.prepare_seconds) /
                           (pb->refinement.adjust_seconds + pb->refinement.prepare_seconds))
        << "\n";
    const auto& gl = pl->metrics.ground_truth;
    const auto& gb = pb->metrics.ground_truth;
    if (gl && gb && gl->num_pairs > 0 && gb->num_pairs > 0)
      out << "pointless / point-based: relative rotation error median "
          << FormatNumber("%.3f", gl->rel_rot_err_deg_median / gb->rel_rot_err_deg_median) << ", max "
          << FormatNumber("%.3f", gl->rel_rot_err_deg_max / gb->rel_rot_err_deg_max)
          << ", translation direction error median "
          << FormatNumber("%.3f", gl->rel_dir_err_deg_median / gb->rel_dir_err_deg_median) << "\n";
  }
  if (pl && pl->refinement.details.contains("relinearizations")) {
    const nlohmann::json& d = pl->refinement.details;
    auto number = [](const nlohmann::json& v) { return v.is_number() ? v.get<double>() : kNaN; };
    out << "pointless: local models' misfit " << FormatNumber("%.3f", number(d["misfit_ratio_initial"]))
        << (d["relinearizations"].get<int>() > 0
                ? " -> " + FormatNumber("%.3f", number(d["misfit_ratio"])) + " after " +
                      std::to_string(d["relinearizations"].get<int>()) + " re-linearisations (" +
                      FormatNumber("%.2f", number(d["relinearization_seconds"])) + " s of local hessian passes)"
                : " (consistent: no re-linearisation)")
        << "\n";
  }
  if (!result.sweep.empty()) {
    out << "\nOutlier sweep (final sigma, px)\n";
    std::snprintf(line, sizeof(line), "%-10s %8s %9s %12s %7s %12s %7s\n", "fraction", "pairs", "triplets",
                  "pointless", "images", "averaging", "images");
    out << line;
    for (const SweepPoint& p : result.sweep) {
      std::snprintf(line, sizeof(line), "%-10.3f %8d %9d %12s %7d %12s %7d %s\n", p.fraction, p.pairs_corrupted,
                    p.triplets_corrupted, FormatNumber("%.4f", p.sigma_pointless).c_str(), p.images_pointless,
                    FormatNumber("%.4f", p.sigma_averaging).c_str(), p.images_averaging, p.error.c_str());
      out << line;
    }
  }
}

std::string ConvergencePlot(const BenchmarkResult& result) {
  std::vector<PlotSeries> series;
  for (const MethodOutcome& m : result.methods) {
    PlotSeries s;
    s.name = DisplayName(m.method);
    for (size_t i = 0; i < m.convergence.size(); ++i) {
      s.x.push_back(static_cast<double>(i));
      s.y.push_back(m.convergence[i]);
    }
    series.push_back(s);
  }
  PlotOptions o;
  o.title = "Convergence: sigma per iteration (paper Figure 3)";
  o.x_label = "iteration";
  o.y_label = "sigma (px)";
  o.log_y = true;
  return LinePlotSvg(series, o);
}

std::string OutlierSweepPlot(const BenchmarkResult& result) {
  PlotSeries pl{"Ours_BA (pointless)", {}, {}}, av{"Aver_BA", {}, {}};
  for (const SweepPoint& p : result.sweep) {
    pl.x.push_back(100.0 * p.fraction);
    pl.y.push_back(p.sigma_pointless);
    av.x.push_back(100.0 * p.fraction);
    av.y.push_back(p.sigma_averaging);
  }
  PlotOptions o;
  o.title = "Sensitivity to relative-rotation outliers (paper Figure 4)";
  o.x_label = "outliers (% of relative rotations)";
  o.y_label = "final sigma (px)";
  o.log_y = true;
  return LinePlotSvg({pl, av}, o);
}

std::string BenchmarkOptions::Check() const {
  if (const std::string p = mapper.Check(); !p.empty()) return p;
  if (const std::string p = refinement.Check(); !p.empty()) return p;
  if (const std::string p = evaluation.Check(); !p.empty()) return "evaluation." + p;
  return CheckRangesAt({{"outlier_sweep", outlier_sweep}}, "BenchmarkOptions");
}

}  // namespace pgba
