// The pointless global bundle adjustment (paper section 3, eq. 5) and the Aver_BA baseline
// (the same relative motions averaged with scalar weights instead of the local Hessians).
//
// Unknowns: every global pose (PoseBlock: [C, omega], R = R0 Exp(omega)) and 7 similarity
// parameters per triplet (motion_similarity.h). Cost: sum_s w_s rho_s(|W_s (x_s - x0_s)|^2)
// with rho_s Huber and w_s the IRLS weight from the triplet's fitting error. Solved by
// Ceres (Levenberg-Marquardt, SPARSE_SCHUR, similarity blocks eliminated first) in IRLS
// rounds; between rounds the weights are recomputed and the rotations re-linearised.
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

struct GlobalBAOptions {
  TripletWeighting weighting = TripletWeighting::kHessian;
  GaugeFixing gauge = GaugeFixing::kFixPoseAndScale;
  SimilarityInit similarity_init = SimilarityInit::kFromPoses;
  // IRLS rounds (each a Ceres solve followed by re-weighting and re-linearisation).
  int max_rounds = 4;
  // Stop the rounds when a round lowers the cost by less than this fraction (rounds after
  // the first only polish the re-weighted fit: 0.4%, 0.07%, 0.02% on a 500-image block).
  double round_tolerance = 1e-3;
  // Levenberg-Marquardt of each round, both solvers (the motion-block solver and Ceres'
  // sparse Schur, motions eliminated first). Config keys:
  //  - max_iterations_per_round (solver.max_iterations) 25;
  //  - function_tolerance 1e-6, parameter_tolerance 1e-8: the point-based baseline's
  //    (BundleAdjusterOptions), so that the benchmark times both to the same stopping rule.
  //    Sigma is final after 2-3 iterations; tighter tolerances only add iterations.
  //  - initial_trust_region_radius 1e8: the first damping diag(J^T J) / radius. The motions'
  //    models are quadratic in the poses up to the rotations and similarities (gain ratio 1.000
  //    at every step), so the solve starts near Gauss-Newton: from Ceres' 1e4 the damping held
  //    back the weak directions (the motions' scales) and the radius grew 3x per step, 7 + 5
  //    iterations on a 70-image orbit where 1e8 takes 3 + 2 to the same optimum.
  //  - embedded_similarity_iterations 1: Gauss-Newton iterations on each motion's similarity
  //    after every pose step of the motion-block solver, the poses held (variable projection
  //    in effect: why in motion_normal_equations.cc, OptimizeSimilarity). Measured on the
  //    long-focal loop seed 1, the last re-linearised solve: 0 crawled 25 iterations (the cap)
  //    at gain ratio ~0.63 along the scale valley, cost 875.6 -> 866.9 and still falling; 1
  //    converged in 12 to 866.6. 0: the plain joint step.
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
  // Fitting error of triplet s: e_s = |W_s (x_s - x0_s)| / n_s with n_s the residual norm of
  // a 1 px pixel error (sqrt(gamma/M) for kHessian, 1 for kScalar); robust scale sigma = the
  // median of e_s. IRLS weight w_s = 1 / (1 + (e_s / (irls_factor sigma))^2) (Cauchy);
  // irls_factor <= 0 disables the reweighting (w_s = 1).
  double irls_factor = 3.0;
  // Huber threshold on |r_s|: huber_factor * sigma * n_s; <= 0 disables the Huber loss.
  double huber_factor = 3.0;
  // Aver_BA scalar weights: rotation sigma (radians) and position sigma as a fraction of the
  // triplet's median point depth L_s (so both are angles seen from the scene). Only their
  // ratio matters: the robust scale normalises the rest.
  double scalar_rotation_sigma = 1e-3;
  double scalar_position_sigma = 1e-3;
  // --- Re-linearisation of the local models (RelinearizedGlobalBA; pointless BA only) ---
  // Each h_s is the curvature of triplet s's cost at its own solution x0_s, and the global
  // cost uses it as an exact quadratic wherever the solution lands. When h_s is extremely
  // anisotropic (narrow-field triplets: 1e8 between the stiffest and the weakest informative
  // directions), the solution's deviation along the weak directions (pivots about the scene)
  // is large enough that second-order terms of the chart and of the similarity gauge reach
  // the stiff directions, many times the noise there: the quadratics then disagree with
  // the truth, and the global BA averages wrong models. The remedy is Gauss-Newton on the
  // triplets' own costs (paper eq. 1): re-run each triplet's local BA step at the pose the
  // global solution predicts for it (points re-triangulated, no iteration), take h_s and the
  // gradient g_s there (paper eq. 3, hence LocalHessian::newton_step), and solve again.
  // At most this many re-linearisations; 0 = never (the paper's single linearisation).
  int max_relinearizations = 3;
  // Re-linearise only when the models disagree with their consensus: when the median over
  // motions of e_s^2 / ((6N - 7) sigma_s^2) (e_s the fitting error, sigma_s the motion's
  // pixel noise from its local BA residuals) exceeds this; <= 0: always. Consistent models
  // sit well below 1 at the solution (it lies between them): 0.29-0.36 on the wide-angle
  // synthetic scenes, 0.14-0.18 for 7-view motions. The long-focal loops with triplets sit at
  // 0.99-1.4 (seed 7: 0.994, where a threshold of 1 let sigma end at 1.24x point-based;
  // re-linearised, 1.018x).
  double relinearize_misfit = 0.5;
  // Stop when the solution moved from the linearisation points by less than this many noise
  // sigmas (median over triplets of |W_s (x_s - x_lin)| / (unit_s sigma_s)).
  double relinearize_tolerance = 0.5;
  // Checked re-linearisation: every pass runs (no misfit trigger), and each solve but the last
  // (which would need one more pass) is kept only if the true robust reprojection cost at it (points re-triangulated:
  // LocalHessian::robust_cost) is lower than at the last kept poses; a step that raises it
  // ends the passes at the last kept poses (the initial ones if the first step is refused).
  // For models taken away from the solution (whole-track motions at the initial poses), where
  // the global BA is Gauss-Newton on the point-based cost with the points eliminated. Stops
  // on relinearize_tolerance, or when a kept step lowers the cost by less than
  // relinearize_cost_tolerance (relative).
  bool relinearize_checked = false;
  double relinearize_cost_tolerance = 1e-4;
  // function_tolerance of a checked pass's solve whose solution is re-linearised next (every
  // solve but the last): the models re-taken there move the cost by ~10% (orbit 472 -> 524),
  // so converging on the old models past 1e-3 buys nothing. Measured on the synthetic
  // orbit, aerial and planar scenes: the iteration it saves predicted a decrease of 1e-7 of
  // the cost (3 -> 2 iterations on orbit and aerial, 6 -> 5 on planar).
  double relinearized_function_tolerance = 1e-3;
  // max_relinearizations when the local Hessians hold intrinsic unknowns (self-calibration):
  // the start is then only a prior, far from the solution, and Gauss-Newton needs more passes
  // (the cost tolerance ends them once converged). Measured on the synthetic aerial block,
  // k -0.08, the view-graph focal 4.7% off: 1 pass 0.47 deg median relative rotation error,
  // 4 passes 0.066 deg (point-based 0.052). On the long-focal loop seed 1 (k1 -0.08, prior 15%
  // long) the cost still fell 6% per pass at the 5th: 5 passes left 7.4x the true lens's
  // relative rotation error, 11 (converged) 1.00x. Orbit, aerial, planar and the rendered room
  // stop after 2-4, the real sets after 4 or on a refused step: unchanged by the cap.
  int max_relinearizations_self_calibrating = 20;
  // max_relinearizations when the motions were linearised at the triplets' pointless BA
  // because the initial poses were far (LocalMotionOptions::triplet_start_misfit): Gauss-Newton
  // then still has two steps to go. Measured on the long-focal loops, seed 3: 1 pass 1.40x
  // the point-based median relative rotation error (max 1.57x), 2 passes 1.03x (1.17x). Two
  // passes stop short of convergence, where the result depends on the path at the rounding
  // level (session 17: re-triangulation from the previous pass's points moved longfocal:1's max
  // ratio 0.919 -> 1.552 at 2 passes); 3 passes converge (the cost tolerance ends them; 5 stop
  // at 3 too): seeds 1-4 median 0.92-1.00x, max 0.89-0.99x.
  int max_relinearizations_far_start = 3;
  // Damped outer loop of the checked re-linearisation (Levenberg-Marquardt across the passes):
  // a step that raises the true robust cost is solved again from the same linearisation as one
  // Levenberg-Marquardt step (damping diag(J^T J) / radius), the radius starting at
  // relinearize_damping_radius and halved, quartered, ... at each further refusal; a kept damped
  // step grows it by the gain ratio of the true cost (Ceres' rule), back to Gauss-Newton's
  // undamped solve once it reaches initial_trust_region_radius. At most relinearize_damped_steps
  // refusals per adjustment (each one more pass); 0 (default): a refused step ends the passes.
  // Off by default: measured on temple_sparse_ring with a wrong focal prior (docs/measurement_history.md, issue 14)
  // it lowers the true cost past a refused step (benchmark tracks at x1.10: 447 -> 425, the
  // point-based BA's fit) but not the rotation errors, which sit in local minima of the
  // truncated cost (observations beyond LocalHessianOptions::max_reprojection_px dropped at
  // every re-linearisation: 1-3% fewer inliers than the point-based BA on the same tracks);
  // where no step is refused (every synthetic scene at the default tolerances, calibrated or
  // self-calibrating) it changes nothing.
  int relinearize_damped_steps = 0;
  double relinearize_damping_radius = 1e4;
  // Redescending first passes of the checked re-linearisation when the local Hessians hold
  // intrinsic unknowns (self-calibration: the start is only a prior): up to this many passes
  // on local Hessians taken with LocalHessianOptions::loss "cauchy" (the point-based BA's
  // first pass: every observation of a triangulated track up to cauchy_max_reprojection_px,
  // none dropped at 4 px for good), until they converge (the passes' own stopping rules); then
  // the local Hessians re-taken there with the configured loss and the checked passes as
  // without. 0: off. Off by default, measured on temple_sparse_ring with a wrong focal prior
  // (docs/measurement_history.md, issue 14): on fixed tracks (N 20) it reaches the point-based BA's rotations at
  // x1.08-1.12 and x0.92 (rel. 0.17-0.25 deg; default 0.25-0.32, Sim3 up to 1.8 deg), in the
  // whole pipeline it ends worse (0.87 deg against 0.21-0.56): both losses' passes stop at a
  // refused step that the models price at almost nothing (a motion's own Newton step lies far
  // along a direction its h hardly sees: focal against camera distance), along which the
  // re-triangulated true cost jumps (points dropping out) and then climbs far above them.
  int relinearize_robust_passes_self_calibrating = 0;
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
  visit("max_relinearizations_self_calibrating", o.max_relinearizations_self_calibrating);
  visit("max_relinearizations_far_start", o.max_relinearizations_far_start);
  visit("relinearize_damped_steps", o.relinearize_damped_steps);
  visit("relinearize_damping_radius", o.relinearize_damping_radius);
  visit("relinearize_robust_passes_self_calibrating", o.relinearize_robust_passes_self_calibrating);
}
PGBA_JSON_FROM_FIELDS(GlobalBAOptions)

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
  // Re-linearisations done (RelinearizedGlobalBA), the time of their local Hessian passes
  // (included in `seconds`), and the last one's median displacement in noise sigmas.
  int relinearizations = 0;
  double relinearization_seconds = 0.0;
  double relinearization_displacement = std::numeric_limits<double>::quiet_NaN();
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
// max_relinearizations): PointlessGlobalBA; then, if the misfit trigger fires, up to
// max_relinearizations times: every used triplet's local Hessian recomputed from `tracks`
// at the local poses the current solution predicts (lh_options with max_iterations = 0),
// and PointlessGlobalBA again from the current poses. The callback sees one continuous
// iteration count; the summary adds up iterations, rounds and time over the solves.
GlobalBAResult RelinearizedGlobalBA(const Reconstruction& tracks, const LocalHessianOptions& lh_options,
                                    const std::map<uint32_t, Pose>& initial_poses,
                                    const std::vector<LocalMotion>& motions, const std::vector<LocalHessian>& hessians,
                                    const GlobalBAOptions& options, const GlobalBAIterationCallback& callback = nullptr,
                                    const GcpInput* gcps = nullptr);

// Aver_BA: the same problem and code path with TripletWeighting::kScalar.
GlobalBAResult AveragingGlobalBA(const std::map<uint32_t, Pose>& initial_poses, const std::vector<LocalMotion>& motions,
                                 const std::vector<LocalHessian>& hessians, const GlobalBAOptions& options,
                                 const GlobalBAIterationCallback& callback = nullptr, const GcpInput* gcps = nullptr);

}  // namespace pgba
