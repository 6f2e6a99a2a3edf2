// The pointless global bundle adjustment (paper section 3, eq. 5) and the Aver_BA baseline
// (the same relative motions averaged with scalar weights instead of the local Hessians).
//
// Unknowns: every global pose (PoseBlock: [C, omega], R = R0 Exp(omega)), 7 similarity
// parameters per relative motion (motion_similarity.h) and, with self-calibration, the
// intrinsic unknowns of each camera. Cost: sum_s w_s rho_s(|W_s (x_s - x0_s - n_s)|^2), with
// W_s^T W_s = h_s the motion's local Hessian (motion_residual.h).
//
// What runs by default (the entry is RelinearizedGlobalBA): the motions are whole-track
// motions (local_hessian/whole_track_motions.h), so the sum of their h_s is the point-based
// BA's reduced camera system. The motions carry no robust loss and no IRLS weight (rho_s the
// identity, w_s = 1: the observations are robustified inside each h_s), so each solve is one
// Levenberg-Marquardt solve on normal equations assembled motion by motion
// (motion_normal_equations.h, SolveMotionBlocks), the gauge held by one pose and one centre
// coordinate. After each solve the local Hessians are re-taken where the solution puts the
// motions (relinearization.cc) and the step is kept only if the true robust reprojection cost
// falls: Gauss-Newton on the point-based cost with the points eliminated, until converged.
//
// The paper's triplet method (PaperTripletGlobalBAOptions, configs/paper_triplets.json) adds a
// Huber loss and IRLS reweighting of the motions by their fitting error, solved by Ceres
// (Levenberg-Marquardt, SPARSE_SCHUR, similarity blocks eliminated first) in IRLS rounds, and
// re-linearises only when the models disagree with their consensus. GCPs (gcp_residual.h) also
// take the Ceres path.
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "modules/gcp/gcp_constraint.h"
#include "modules/global_ba/motion_block_solver_options.h"
#include "modules/local_hessian/local_hessian.h"
#include "pgba/geometry/pose.h"
#include "pgba/geometry/sim3.h"
#include "pgba/scene/view_graph.h"
#include "pgba/util/json_fields.h"

namespace pgba {

// W_s of the residual W_s (x_s - x0_s).
enum class TripletWeighting {
  kHessian,  // W_s = D_s V_s, W_s^T W_s = h_s (pointless BA, paper eq. 5)
  kScalar,   // Aver_BA: diag(1 / (sigma_p L_s) on positions, 1 / sigma_omega on rotations)
};
NLOHMANN_JSON_SERIALIZE_ENUM(TripletWeighting, {{TripletWeighting::kHessian, "hessian"},
                                                {TripletWeighting::kScalar, "scalar"}})

// The 7-dof gauge of the global problem (a similarity of the whole block).
enum class GaugeFixing {
  // The reference triplet's similarity is held constant (the paper's choice): the global
  // frame is then that triplet's local frame mapped back by its initial similarity; it is
  // held through that triplet's (weak) gauge prior, which is enough for a direct solver.
  kFixSimilarity,
  // The reference triplet's first pose is held constant and one centre coordinate of its
  // second pose (the largest component of their baseline): the global frame stays the
  // initial one, held strongly.
  kFixPoseAndScale,
};
NLOHMANN_JSON_SERIALIZE_ENUM(GaugeFixing, {{GaugeFixing::kFixSimilarity, "fix_similarity"},
                                           {GaugeFixing::kFixPoseAndScale, "fix_pose_and_scale"}})

enum class SimilarityInit {
  kFromPoses,    // alpha from the camera rotations, lambda / beta from the centres (default)
  kFromTriplet,  // LocalMotion::global_to_local as given by the averaging stage
};
NLOHMANN_JSON_SERIALIZE_ENUM(SimilarityInit, {{SimilarityInit::kFromPoses, "from_poses"},
                                              {SimilarityInit::kFromTriplet, "from_triplet"}})

// The defaults are pgba's method, whole-track motions (whole_track_motions.h), where the sum of
// the local Hessians is the point-based BA's reduced camera system: no robust loss or IRLS
// weight on the motions (observations are robustified inside the local Hessians, with the
// point-based BA's Huber and 4 px filter), one round per solve, and the local Hessians
// re-linearised at each solution until the true robust reprojection cost has converged
// (Gauss-Newton on the point-based cost with the points eliminated). The paper's triplet
// method is PaperTripletGlobalBAOptions() (configs/paper_triplets.json states it for a run).
struct GlobalBAOptions {
  TripletWeighting weighting = TripletWeighting::kHessian;
  GaugeFixing gauge = GaugeFixing::kFixPoseAndScale;
  SimilarityInit similarity_init = SimilarityInit::kFromPoses;
  // IRLS rounds per solve (each a Levenberg-Marquardt solve followed by re-weighting); 1: the
  // motions carry no IRLS weight to update.
  int max_rounds = 1;
  // Stop the rounds when a round lowers the cost by less than this fraction.
  double round_tolerance = 1e-3;
  // Levenberg-Marquardt of each solve, both solvers (the motion-block solver and Ceres'
  // sparse Schur, motions eliminated first). Config keys:
  //  - max_iterations_per_round (solver.max_iterations) 25: a safety cap, the tolerances end
  //    a solve;
  //  - function_tolerance 1e-6, parameter_tolerance 1e-8: the point-based baseline's
  //    (BundleAdjusterOptions), so that the benchmark times both to the same stopping rule;
  //  - initial_trust_region_radius 1e8: the first damping diag(J^T J) / radius. The motions'
  //    models are quadratic in the poses up to the rotations and similarities, so the solve
  //    starts near Gauss-Newton (a small radius holds back the weak directions, the motions'
  //    scales, for several iterations);
  //  - embedded_similarity_iterations 1: Gauss-Newton iterations on each motion's similarity
  //    after every pose step of the motion-block solver, the poses held (variable projection
  //    in effect: why in motion_normal_equations.cc, OptimizeSimilarity); 0: the plain joint
  //    step, which crawls along the scale valley of long narrow-field blocks;
  //  - num_threads 1 (Ceres threads): bit-identical results whatever the machine; more
  //    threads make Ceres' reductions scheduling-dependent (last bits). 0 = hardware
  //    concurrency.
  // solver.stop_at_refused_step is no config key: the checked re-linearisation sets it.
  MotionBlockSolverOptions solver = [] {
    MotionBlockSolverOptions s;
    s.linear_solver_type = ceres::SPARSE_SCHUR;
    s.max_iterations = 25;
    s.initial_trust_region_radius = 1e8;
    s.embedded_similarity_iterations = 1;
    return s;
  }();
  // Fitting error of motion s: e_s = |W_s (x_s - x0_s)| / n_s with n_s the residual norm of
  // a 1 px pixel error (sqrt(gamma/M) for kHessian, 1 for kScalar); robust scale sigma = the
  // median of e_s. IRLS weight w_s = 1 / (1 + (e_s / (irls_factor sigma))^2) (Cauchy);
  // irls_factor <= 0 disables the reweighting (w_s = 1).
  double irls_factor = 0.0;
  // Huber threshold on |r_s|: huber_factor * sigma * n_s; <= 0 disables the Huber loss.
  double huber_factor = 0.0;
  // Aver_BA scalar weights: rotation sigma (radians) and position sigma as a fraction of the
  // motion's median point depth L_s (so both are angles seen from the scene). Only their
  // ratio matters: the robust scale normalises the rest.
  double scalar_rotation_sigma = 1e-3;
  double scalar_position_sigma = 1e-3;
  // --- Re-linearisation of the local models (RelinearizedGlobalBA; pointless BA only) ---
  // Each h_s is the curvature of motion s's cost at its linearisation point x0_s, and the
  // global cost uses it as an exact quadratic wherever the solution lands. Away from x0_s the
  // quadratic no longer agrees with the motion's cost (second-order terms of the chart and the
  // similarity gauge, points that move). The remedy is Gauss-Newton on the motions' own costs
  // (paper eq. 1): re-take each local Hessian at the pose the global solution predicts for it
  // (points re-triangulated, no local iteration), with the gradient there (paper eq. 3,
  // LocalHessian::newton_step), and solve again, until converged.
  //
  // The stopping rule (relinearize_checked, the default): after each solve the models are
  // re-taken there and the true robust reprojection cost (LocalHessian::robust_cost, points
  // re-triangulated) is compared with the last kept one. The passes stop, converged, when
  //  - a kept step lowers the true cost by less than relinearize_cost_tolerance (relative), or
  //  - the step moved the motions by less than relinearize_tolerance noise sigmas (the
  //    largest over the motions of |W_s (x_s - x_lin)| / (unit_s sigma_s): no motion moves
  //    further than the noise); after the first re-take this is tested before re-taking the
  //    models, and such a step is kept as solved (its models hold to second order there), or
  //  - a step raises the true cost (refused: the last kept poses are returned; converged
  //    when that step was already below the cost tolerance, else reported as stopped short).
  // max_relinearizations is only a safety net: reaching it is reported as "not converged" in
  // the log and in report.json. 0: the first solve's poses, never re-linearised.
  int max_relinearizations = 30;
  double relinearize_cost_tolerance = 1e-5;
  double relinearize_tolerance = 0.25;
  // The paper's unchecked re-linearisation (relinearize_checked false): each solve taken as it
  // is, re-linearised only when the models disagree with their consensus: when the median over
  // motions of e_s^2 / ((6N - 7) sigma_s^2) (e_s the fitting error, sigma_s the motion's pixel
  // noise from its local BA residuals) exceeds relinearize_misfit (<= 0: always); the passes
  // stop when the median displacement falls below relinearize_tolerance, or at
  // max_relinearizations.
  bool relinearize_checked = true;
  double relinearize_misfit = 0.0;
  // Graduated outlier threshold of the checked passes: from a start far from the solution
  // most observations lie beyond the local Hessians' outlier threshold
  // (LocalHessianOptions::max_reprojection_px, 4 px) and would be dropped from the first
  // models, leaving cameras that then hold too few to move back. When the median reprojection
  // error at the start (tracks re-triangulated) times start_outlier_factor exceeds that
  // threshold, the passes first run on models taken with this wider threshold, until they
  // converge or the same test no longer finds the poses far, then the models are re-taken
  // there with the configured threshold and the passes run again to convergence (the true cost
  // is compared within one threshold only). <= 0: off.
  double start_outlier_factor = 3.0;
  // function_tolerance of a solve whose solution is re-linearised and checked next: the
  // models re-taken there move the cost by more than this, so converging on the old models
  // further buys nothing (the last pass's solve gets no tighter: the cost tolerance of the
  // passes is what says converged).
  double relinearized_function_tolerance = 1e-3;
  // Empty when valid, else one line naming the first field out of its valid range (the
  // ranges of io/option_ranges.cc) or breaking a rule between fields.
  std::string Check() const;
};
template <class Visit>
void JsonFields(GlobalBAOptions& o, Visit&& visit) {
  visit("weighting", o.weighting);
  visit("gauge", o.gauge);
  visit("similarity_init", o.similarity_init);
  visit("max_rounds", o.max_rounds);
  visit("max_iterations_per_round", o.solver.max_iterations);
  visit("round_tolerance", o.round_tolerance);
  visit("function_tolerance", o.solver.function_tolerance);
  visit("parameter_tolerance", o.solver.parameter_tolerance);
  visit("initial_trust_region_radius", o.solver.initial_trust_region_radius);
  visit("embedded_similarity_iterations", o.solver.embedded_similarity_iterations);
  visit("irls_factor", o.irls_factor);
  visit("huber_factor", o.huber_factor);
  visit("scalar_rotation_sigma", o.scalar_rotation_sigma);
  visit("scalar_position_sigma", o.scalar_position_sigma);
  visit("num_threads", o.solver.num_threads);
  visit("max_relinearizations", o.max_relinearizations);
  visit("relinearize_misfit", o.relinearize_misfit);
  visit("relinearize_tolerance", o.relinearize_tolerance);
  visit("relinearize_checked", o.relinearize_checked);
  visit("relinearize_cost_tolerance", o.relinearize_cost_tolerance);
  visit("relinearized_function_tolerance", o.relinearized_function_tolerance);
  visit("start_outlier_factor", o.start_outlier_factor);
}
PGBA_JSON_FROM_FIELDS(GlobalBAOptions)

// The paper's triplet method (section 3): Huber loss and IRLS reweighting of the motions by
// their fitting error (irls_factor 3, huber_factor 3, 4 rounds), the local models re-linearised
// only when they disagree with their consensus (relinearize_misfit 0.5), each solve taken
// unchecked, at most 3 passes. configs/paper_triplets.json states the same values.
GlobalBAOptions PaperTripletGlobalBAOptions();

// State handed to the iteration callback after every Levenberg-Marquardt iteration (and
// once before the first, iteration 0): e.g. to evaluate sigma for a convergence curve.
struct GlobalBAIteration {
  int iteration = 0;  // counted over all rounds
  int round = 0;
  double cost = 0.0;  // under this round's weights
  const std::map<uint32_t, Pose>* poses = nullptr;
};
using GlobalBAIterationCallback = std::function<void(const GlobalBAIteration&)>;

struct GlobalBASummary {
  int iterations = 0;  // Levenberg-Marquardt iterations over all rounds
  int rounds = 0;
  // Cost after each iteration (index 0: initial), under the weights of its round.
  std::vector<double> cost_per_iteration;
  double initial_cost = 0.0;
  double final_cost = 0.0;
  double seconds = 0.0;
  // Unknowns: 6 per pose + 7 per motion + the intrinsic unknowns.
  int num_params = 0;
  int num_poses = 0;
  int num_motions = 0;  // used (report key "triplets_used")
  // Motions not used: hessian not ok, an image without initial pose, or outside the largest
  // rigidly connected component (motions sharing two images).
  int num_motions_excluded = 0;
  // Initial poses of images in no used motion (their pose is not refined or returned).
  std::vector<uint32_t> excluded_images;
  // Motions whose final IRLS weight is below 0.5 (treated as outliers).
  int num_motions_downweighted = 0;
  double robust_scale = 0.0;  // final sigma of the fitting errors (px-like units)
  // With GCPs: residuals added (one per triplet and GCP seen in >= 2 of its images), and
  // whether they fix the gauge (>= 3 non-collinear GCPs; no pose or similarity held then).
  int num_gcp_residuals = 0;
  bool gcp_gauge = false;
  // Median normalised misfit e_s^2 / (11 sigma_s^2) at the end (kHessian; NaN otherwise)
  // and after the first solve with the stage's local Hessians (what the trigger saw).
  double misfit_ratio = std::numeric_limits<double>::quiet_NaN();
  double misfit_ratio_initial = std::numeric_limits<double>::quiet_NaN();
  // Re-linearisations kept (RelinearizedGlobalBA), the time of their local Hessian passes
  // (included in `seconds`), and the last step's displacement in noise sigmas (the checked
  // passes: the largest over the motions; the unchecked ones: the median).
  int relinearizations = 0;
  double relinearization_seconds = 0.0;
  double relinearization_displacement = std::numeric_limits<double>::quiet_NaN();
  // One entry per pass of the checked re-linearisation: the true robust reprojection cost
  // where the pass's models were taken (entry 0: the start), whether the step that led
  // there was kept, and its displacement in noise sigmas (NaN for the start).
  struct Pass {
    // The true robust cost where the step ended; NaN for a last step kept without re-taking
    // its models (below relinearize_tolerance).
    double robust_cost = 0.0;
    bool kept = true;
    double displacement = std::numeric_limits<double>::quiet_NaN();
    double outlier_px = 0.0;  // the models' outlier threshold (the cost is truncated there)
  };
  std::vector<Pass> passes;
  // Why the passes ended: "cost_tolerance", "step_tolerance", "refused_step",
  // "max_relinearizations" (the safety net: not converged), "misfit_below_threshold" (the
  // unchecked passes' trigger did not fire), "no_relinearization" (max_relinearizations 0).
  std::string stop_reason;
  bool converged = true;
  // The start's median reprojection error (px) and the wider threshold of the first phase
  // (start_outlier_factor; 0 when the passes ran at the configured threshold only).
  double start_median_px = 0.0;
  double start_outlier_px = 0.0;
  // The motion-block solver's trust region radius at the end of the last solve (0 when Ceres
  // ran it): a re-linearised solve starts there (relinearization.cc, SolveAgain).
  double final_trust_region_radius = 0.0;
};

// Self-calibration: one camera's intrinsic unknowns of the global BA (paper, "Self-calibrating
// bundle adjustment": global unknowns per camera, observed through every motion's h).
struct GlobalIntrinsics {
  std::vector<int> free;   // indices into Camera::params
  Eigen::VectorXd initial;  // their values before the adjustment
  Eigen::VectorXd values;   // and after
  // Standard deviations: sqrt(diag((J^T J)^-1)) times the pixel noise sigma of the motions'
  // observations (NaN where not computed: the Ceres path with a robust loss or GCPs).
  Eigen::VectorXd stddev;
};

struct GlobalBAResult {
  std::map<uint32_t, Pose> poses;  // refined poses of the images of the used triplets
  // Per camera with intrinsic unknowns in the local Hessians (empty: none).
  std::map<uint32_t, GlobalIntrinsics> intrinsics;
  // Final global->local similarity per input triplet (identity for unused ones) and the
  // triplet's final IRLS weight (0 for unused ones).
  std::vector<Sim3> similarities;
  std::vector<double> irls_weights;
  GlobalBASummary summary;
};

// Pointless global BA. `hessians` come from ComputeLocalHessians on `motions` (matched by
// LocalHessian::motion_index; a mismatch of image ids is an InputError). Uses
// options.weighting (kHessian by default). Optional `gcps` (paper, "Inclusion of ground
// control points"; gcp_residual.h): the initial poses must already be in the GCP frame
// (AlignToGcps of gcp_alignment.h).
GlobalBAResult PointlessGlobalBA(const std::map<uint32_t, Pose>& initial_poses, const std::vector<LocalMotion>& motions,
                                 const std::vector<LocalHessian>& hessians, const GlobalBAOptions& options,
                                 const GlobalBAIterationCallback& callback = nullptr, const GcpInput* gcps = nullptr);

// Pointless global BA with re-linearised local models (GlobalBAOptions::
// max_relinearizations): PointlessGlobalBA; then, up to max_relinearizations times, every
// used motion's local Hessian re-taken from `tracks` at the local poses the current solution
// predicts (lh_options with max_iterations = 0) and PointlessGlobalBA again from the current
// poses. With relinearize_checked (the default) each step is kept only if the true robust
// reprojection cost falls, and the passes stop by the rule of GlobalBAOptions; without it
// (the paper's method) a pass runs only when the misfit trigger fires. The callback sees one
// continuous iteration count; the summary adds up iterations, rounds and time over the solves.
// `hessians` are taken by value and re-taken in place, one model per motion: a caller that no
// longer needs them moves them in (the largest memory of a large block), others copy.
GlobalBAResult RelinearizedGlobalBA(const Reconstruction& tracks, const LocalHessianOptions& lh_options,
                                    const std::map<uint32_t, Pose>& initial_poses,
                                    const std::vector<LocalMotion>& motions, std::vector<LocalHessian> hessians,
                                    const GlobalBAOptions& options, const GlobalBAIterationCallback& callback = nullptr,
                                    const GcpInput* gcps = nullptr);

// Aver_BA: the same problem and code path with TripletWeighting::kScalar.
GlobalBAResult AveragingGlobalBA(const std::map<uint32_t, Pose>& initial_poses, const std::vector<LocalMotion>& motions,
                                 const std::vector<LocalHessian>& hessians, const GlobalBAOptions& options,
                                 const GlobalBAIterationCallback& callback = nullptr, const GcpInput* gcps = nullptr);

}  // namespace pgba
