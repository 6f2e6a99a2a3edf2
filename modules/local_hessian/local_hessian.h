// Local Hessians of the relative motions (paper section 3, "Local bundle adjustment"): per
// motion of N views, the bundle problem in the motion's own frame over its N poses and its
// points, then the 6N x 6N camera reduced matrix h (Schur complement on the points, paper
// eq. 3; 18x18 for a triplet) and its factor W with W^T W = h (paper eq. 5), which the
// pointless global BA consumes.
//
// By default (whole-track motions, whole_track_motions.h) h is taken at the given poses: the
// points triangulated from them, no local BA iteration, every observation of weight 1, h
// factored by LDLT; the global BA's re-linearisation then re-takes it where its solution puts
// the motion. The paper's triplets (PaperTripletLocalHessianOptions) run one local BA
// iteration from the triplet BA's solution with attenuated observations and eigen-decompose
// h = V^T D^2 V.
//
// Chart (ARCHITECTURE.md): per view the 6-vector [c(3), omega(3)] with r = r0 * Exp(omega)
// around the local BA's solution x0 = {r0_k, c0_k}; h is ordered view 0, 1, ..., N-1 of
// LocalMotion::image_ids. Units: observations in pixels, so h is in 1/px^2 (times the
// per-observation weight below).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "modules/local_hessian/symmetric_matrix.h"
#include "pgba/geometry/pose.h"
#include "pgba/optim/intrinsics.h"
#include "pgba/optim/loss_function_options.h"
#include "pgba/optim/solver_options.h"
#include "pgba/scene/reconstruction.h"
#include "pgba/scene/view_graph.h"
#include "pgba/util/json_fields.h"

namespace pgba {

using Matrix18d = Eigen::Matrix<double, 18, 18>;  // a triplet's h
using Vector18d = Eigen::Matrix<double, 18, 1>;

// The 7 directions of a local frame that no reprojection sees (translation, rotation, scale):
// a motion of N views has 6N - 7 informative ones.
constexpr int kGaugeDimension = 7;
inline int InformativeDimension(int num_views) { return 6 * num_views - kGaugeDimension; }

// Where the weak pose prior that fixes the gauge ("all three extrinsics observed") goes.
enum class PriorPlacement {
  // Only into h: the prior is centred at the local BA's solution x0, so it has no gradient
  // there and leaves x0 untouched; it only lifts the 7-dim similarity null space of h. The
  // local BA itself runs without it (Levenberg-Marquardt damping copes with the gauge).
  kHessianOnly,
  // Also as residuals of the local BA, centred at the input poses (the paper's literal
  // "extrinsics treated as observed"); mu is then taken from h at the input poses.
  kLocalBAAndHessian,
};
NLOHMANN_JSON_SERIALIZE_ENUM(PriorPlacement, {{PriorPlacement::kHessianOnly, "hessian_only"},
                                              {PriorPlacement::kLocalBAAndHessian, "local_ba_and_hessian"}})

// Which directions the gauge prior weighs. Charts below: [c / L, omega] (scale-aware).
enum class PriorShape {
  // mu on every coordinate (ARCHITECTURE.md lesson: h + mu I). Also pulls the informative
  // directions towards x0 by mu / lambda_i, i.e. up to ~1% for the weakest ones at 1e-6.
  kIsotropic,
  // mu only on the 7 directions of h's null space: the infinitesimal similarities of the
  // local frame acting on x0 (translation, rotation about the centroid of the centres,
  // scale), orthonormalised. The classical inner-constraint gauge: it leaves every
  // informative direction of h untouched, so mu can be large enough to make the triplet
  // similarities well determined in the global BA.
  kSimilarity,
};
NLOHMANN_JSON_SERIALIZE_ENUM(PriorShape, {{PriorShape::kIsotropic, "isotropic"}, {PriorShape::kSimilarity, "similarity"}})

// How h is factored into the weight W = diag(D) V of the global residual (W^T W = h).
enum class HessianFactor {
  // Eigen decomposition, rows of V orthonormal eigenvectors (paper eq. 5): ~9 (6N)^3 flops.
  kEigen,
  // Pivoted LDL^T, h = P^T L diag(d) L^T P: V = L^T P, D = sqrt(d), (6N)^3 / 3 flops; the same
  // W^T W, so the same residual norm (large whole-track motions, N up to 30-40 views).
  kLdlt,
};
NLOHMANN_JSON_SERIALIZE_ENUM(HessianFactor, {{HessianFactor::kEigen, "eigen"}, {HessianFactor::kLdlt, "ldlt"}})

// Number of motions that use each observation (image id, track id).
using ObservationShares = std::map<std::pair<uint32_t, uint64_t>, int>;

// The local BA's Ceres solve: dense Schur on the points, one thread (the motions are solved
// in parallel outside), `max_iterations` Levenberg-Marquardt iterations.
inline SolverOptions LocalBundleSolverOptions(int max_iterations) {
  SolverOptions solver;
  solver.linear_solver_type = ceres::DENSE_SCHUR;
  solver.max_iterations = max_iterations;
  return solver;
}

// The defaults are pgba's method, whole-track motions (whole_track_motions.h), where the sum of
// the local Hessians must stay the point-based BA's reduced camera system: every observation
// weighs 1 (no attenuation), no rank test (a direction one motion's tracks do not see is seen
// by others), h taken at the given poses (no local BA: the global BA's re-linearisation is the
// next Gauss-Newton step, the points eliminated), factored by LDLT. The paper's triplet method
// is PaperTripletLocalHessianOptions() (configs/paper_triplets.json states it for a run).
struct LocalHessianOptions {
  // The local BA's solve; config key "max_iterations" (solver.max_iterations): its
  // Levenberg-Marquardt iterations (paper: a single iteration from the triplet BA's solution;
  // more converge x0 further, 0 takes h at the input poses).
  SolverOptions solver = LocalBundleSolverOptions(0);
  // Attenuation: each observation's squared residual is weighted by gamma / M with
  // gamma = M Q / (M + Q), i.e. by Q / (M + Q), M the triplet's number of points: every
  // triplet then weighs like ~Q points (paper, implementation details). Q <= 0 or +inf
  // disables it: weight 1 per observation, h is the plain (unattenuated) information and
  // grows with M.
  double attenuation_q = 0.0;
  // Robust loss on the pixel reprojection error of the local BA, of h's IRLS weights and of
  // the robust cost: config key "loss", "huber" (default) or "cauchy" (the point-based BA's
  // first pass: redescending, a camera far off still feels the observations it lost), and
  // its scale "huber_px", 1 px (Huber: the pixel error where it turns linear; Cauchy: where
  // the weight has halved).
  LossFunctionOptions loss = {LossType::kHuber, 1.0};
  // Observations whose reprojection error after triangulation exceeds this (pixels) are left
  // out of the triplet's problem (gross outliers); a point left with < 2 views is dropped.
  // With loss "cauchy" it is only the triangulation's outlier threshold (the point is the
  // inliers' estimate) and observations are kept up to cauchy_max_reprojection_px.
  double max_reprojection_px = 4.0;
  // With loss "cauchy": observations kept up to this (pixels), the robust cost capped there.
  // Beyond ~30 px the Cauchy weight (1 / (1 + (e / huber_px)^2)) is below 1e-3: the cap only
  // keeps the cost of a view that cannot be triangulated finite and comparable.
  double cauchy_max_reprojection_px = 64.0;
  // Triplets with fewer points are rejected (paper: 30).
  int min_points = 30;
  // Gauge prior ("all three extrinsics observed"): mu = prior_relative * largest eigenvalue
  // of h, on the directions chosen by prior_shape.
  PriorShape prior_shape = PriorShape::kSimilarity;
  double prior_relative = 1e-3;
  // If true, mu and the prior's directions are taken in the chart [c / L, omega] with L the
  // median point depth of the triplet (so the prior weighs positions and rotations alike
  // whatever the scale of the local frame: isotropic means mu / L^2 on centres, mu on
  // rotations). If false, in [c, omega] as in the prototype (only sensible for local frames
  // of unit scale).
  bool prior_scale_aware = true;
  PriorPlacement prior_placement = PriorPlacement::kHessianOnly;
  // Rank test: in the scale-aware chart, the (6N - 7)-th largest eigenvalue of h before the
  // prior (the weakest direction that is not a similarity of the local frame; the 11th of a
  // triplet) must be at least this fraction of the largest, or the motion is rejected as
  // ill-conditioned. <= 0: no rank test (the eigenvalues are then not computed: the
  // prior's largest eigenvalue comes from power iterations).
  double min_eigenvalue_ratio = 0.0;
  HessianFactor factor = HessianFactor::kLdlt;
  // Minimum triangulation angle of a triplet point (degrees); 0 keeps every point.
  double min_triangulation_angle_deg = 0.0;
  // TBB threads over triplets; 0 = all available.
  int num_threads = 0;
  // Weight each observation's squared residual by 1 / (number of triplets using it), on top
  // of the attenuation: an observation shared by n triplets then counts once over the whole
  // triplet set, as in a point-based BA, instead of n times (sequences with many triplets per
  // image pair). Off: the paper's attenuation only.
  bool shared_observation_weighting = false;
  // Empty when valid, else one line naming the first field out of its valid range (the
  // ranges of io/option_ranges.cc) or breaking a rule between fields.
  std::string Check() const;
};
template <class Visit>
void JsonFields(LocalHessianOptions& o, Visit&& visit) {
  visit("max_iterations", o.solver.max_iterations);
  visit("attenuation_q", o.attenuation_q);
  visit("loss", o.loss.type);
  visit("huber_px", o.loss.scale);
  visit("max_reprojection_px", o.max_reprojection_px);
  visit("cauchy_max_reprojection_px", o.cauchy_max_reprojection_px);
  visit("min_points", o.min_points);
  visit("prior_shape", o.prior_shape);
  visit("prior_relative", o.prior_relative);
  visit("prior_scale_aware", o.prior_scale_aware);
  visit("prior_placement", o.prior_placement);
  visit("min_eigenvalue_ratio", o.min_eigenvalue_ratio);
  visit("min_triangulation_angle_deg", o.min_triangulation_angle_deg);
  visit("num_threads", o.num_threads);
  visit("shared_observation_weighting", o.shared_observation_weighting);
  visit("factor", o.factor);
}
PGBA_JSON_FROM_FIELDS(LocalHessianOptions)

// The paper's triplet method (section 3): one local BA iteration from the triplet BA's
// solution, each observation attenuated by gamma / M (Q 10), the rank test at 1e-10, h
// eigen-decomposed (eq. 5). configs/paper_triplets.json states the same values.
LocalHessianOptions PaperTripletLocalHessianOptions();

enum class LocalHessianStatus {
  kOk = 0,
  kInvalidInput,    // an image / camera / track of the triplet is missing, or a non-finite local pose
  kTooFewPoints,    // fewer than min_points usable points
  kSolverFailure,   // the local BA failed to evaluate
  kNonFinite,       // NaN or inf in h
  kIllConditioned,  // rank-deficient or ill-conditioned h (min_eigenvalue_ratio)
};
constexpr int kNumLocalHessianStatus = 6;
const char* LocalHessianStatusName(LocalHessianStatus status);

struct LocalHessian {
  int motion_index = -1;  // into the motion list given to ComputeLocalHessians
  std::vector<uint32_t> image_ids;
  LocalHessianStatus status = LocalHessianStatus::kInvalidInput;
  // x0_s: the N local poses after the local BA, the linearisation point of h.
  std::vector<Pose> local_poses;
  // Self-calibration (paper, "Self-calibrating bundle adjustment"): the cameras whose
  // intrinsics are unknowns of h (ascending ids), each one's free parameter indices, and
  // their values at the linearisation point (concatenated in that order, K in all). h, V, g
  // and newton_step then have 6N + K rows: the N poses, then these K intrinsics, which are
  // not affected by the local frame (the global BA compares them with its own directly).
  std::vector<uint32_t> intrinsic_camera_ids;
  std::vector<std::vector<int>> intrinsic_free;
  Eigen::VectorXd intrinsics0;
  // Camera reduced matrix including the gauge prior: h = h_points + prior (6N x 6N). The one
  // (6N + K)^2 matrix a motion keeps, one triangle of it (symmetric_matrix.h): the global BA's
  // normal equations need h itself, and its weight W = diag(D) V (paper eq. 5) is recomputed
  // from h where a residual vector is needed (Factor), not stored beside it.
  SymmetricMatrix h;
  // How W is factored from h (LocalHessianOptions::factor; kEigen for h read from a workspace).
  HessianFactor factor = HessianFactor::kLdlt;
  // Reduced gradient g of paper eq. 3 at local_poses (same chart and weights as h).
  Eigen::VectorXd reduced_gradient;
  // Minimiser of the quadratic model of paper eq. 3 relative to local_poses: -h^-1 g, in
  // h's chart. The global residual is W_s (x_s - x0_s - newton_step), i.e. it keeps the
  // gradient term that paper eq. 5 drops (zero when the local BA converged; not zero when h
  // is re-linearised away from the triplet's optimum, global_ba.h "relinearization").
  Eigen::VectorXd newton_step;
  // The gauge prior added to h (h = h_points + prior), of low rank, as its factor F with
  // prior = F F^T (6N + K rows; 7 columns for PriorShape::kSimilarity), and its mu.
  Eigen::MatrixXd prior_factor;
  double prior_mu = 0.0;
  // Weight of each observation's squared residual, gamma / M (1 if disabled); with
  // shared_observation_weighting its mean over the triplet's observations.
  double observation_weight = 1.0;
  // Median point depth L in the local frame (the length of the scale-aware chart).
  double depth_scale = 1.0;
  // Eigenvalue ratio of the rank test ((6N-7)-th largest / largest, scale-aware chart, no prior);
  // 0 when the rank test is off (not computed).
  double eigenvalue_ratio = 0.0;
  // The points at local_poses and their kept observations, aligned with the motion's track_ids
  // (NaN for a track that gave no point): the start of the next re-linearisation's
  // triangulation.
  std::vector<PointStart> track_points;
  int num_points = 0;
  int num_observations = 0;
  // Unweighted RMS reprojection error (pixels) after the local BA.
  double rms_px = 0.0;
  // RobustCost (local_bundle.h) at local_poses: the motion's share of the point-based cost.
  double robust_cost = 0.0;

  int num_views() const { return static_cast<int>(image_ids.size()); }
  int num_intrinsics() const { return static_cast<int>(intrinsics0.size()); }
  // The gauge prior as a matrix, F F^T.
  Eigen::MatrixXd Prior() const { return prior_factor * prior_factor.transpose(); }
  // h = V^T diag(D)^2 V by `factor`: with kEigen rows of V are orthonormal eigenvectors, D the
  // square roots of the eigenvalues (negative ones clamped to 0), ascending; with kLdlt
  // V = L^T P and D the square roots of the pivots. Deterministic: the same h gives the same bits.
  void Factor(Eigen::MatrixXd* V, Eigen::VectorXd* D) const;
};

struct LocalHessianResult {
  std::vector<LocalHessian> hessians;  // one per input motion, same order
  std::array<int, kNumLocalHessianStatus> status_counts{};
  int num_ok() const { return status_counts[0]; }
};

// {status name: count} over every status, "ok" included (report.json records).
nlohmann::json LocalHessianStatusCounts(const LocalHessianResult& result);

// One motion (paper eqs. 1-3 and the decomposition of eq. 5). `shares` (for
// shared_observation_weighting; nullptr: weight 1) counts the motions using each observation.
// `free` (nullptr: none): the intrinsics that are unknowns (optim/intrinsics.h).
LocalHessian ComputeLocalHessian(const Reconstruction& tracks, const LocalMotion& motion, int motion_index,
                                 const LocalHessianOptions& options, const ObservationShares* shares = nullptr,
                                 const FreeIntrinsics* free = nullptr);

// The ObservationShares of a motion set: for every motion, track and view that observes it.
ObservationShares CountObservationShares(const Reconstruction& tracks, const std::vector<LocalMotion>& motions);

// Every motion, in parallel (TBB; results do not depend on the thread count). Logs the
// counts of rejected motions per reason. `shares`: shared_observation_weighting counted over
// another motion set (e.g. all of them when re-computing a subset); nullptr: counted here.
LocalHessianResult ComputeLocalHessians(const Reconstruction& tracks, const std::vector<LocalMotion>& motions,
                                        const LocalHessianOptions& options, const ObservationShares* shares = nullptr,
                                        const FreeIntrinsics* free = nullptr);

}  // namespace pgba
