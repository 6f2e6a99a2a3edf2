#include "modules/global_ba/global_ba.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <thread>
#include <vector>

#include "modules/global_ba/gcp_residual.h"
#include "modules/global_ba/gcp_terms.h"
#include "modules/global_ba/global_ba_solve.h"
#include "modules/global_ba/motion_normal_equations.h"
#include "modules/global_ba/motion_residual.h"
#include "modules/global_ba/motion_selection.h"
#include "modules/global_ba/motion_similarity.h"
#include "modules/global_ba/motion_weighting.h"
#include "pgba/optim/pose_parameterization.h"
#include "pgba/util/error.h"
#include "pgba/util/id_ordered_map.h"
#include "pgba/util/logging.h"
#include "pgba/util/timer.h"
#include "pgba/util/upper_median.h"

namespace pgba {

using internal::IntrinsicSizes;
using internal::NoiseVariance;
using internal::ResidualDegreesOfFreedom;

std::vector<int> internal::IntrinsicSizes(const LocalHessian& h) {
  std::vector<int> sizes;
  for (const std::vector<int>& free : h.intrinsic_free) sizes.push_back(static_cast<int>(free.size()));
  return sizes;
}

double internal::ResidualDegreesOfFreedom(const LocalHessian& h) {
  return 2.0 * h.num_observations - 3.0 * h.num_points - InformativeDimension(h.num_views());
}

double internal::NoiseVariance(const LocalHessian& h) {
  const double dof = ResidualDegreesOfFreedom(h);
  if (!(dof > 0) || !(h.rms_px > 0)) return std::numeric_limits<double>::quiet_NaN();
  return h.rms_px * h.rms_px * h.num_observations / dof;
}

namespace {

// One used motion: its local Hessian, weight matrix, similarity and IRLS state.
struct MotionTerm {
  const LocalHessian* hessian = nullptr;
  MotionWeight W;  // shared with its residuals (motion_weight.h)
  Eigen::VectorXd newton_step;  // LocalHessian::newton_step (kHessian only; empty: zero)
  double unit = 1.0;  // ResidualUnit
  MotionSimilarity sim;
  double irls_weight = 1.0;
};

// A camera's global intrinsic unknowns: its free parameter values (inline storage, so that they
// sit in the contiguous IdOrderedMap like the poses).
struct IntrinsicsBlock {
  std::vector<int> free;
  Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 8, 1> x;
};

struct Unknowns {
  // Contiguous in id order: Ceres orders the Schur complement's blocks by address (id_ordered_map.h).
  IdOrderedMap<PoseBlock> poses;
  IdOrderedMap<IntrinsicsBlock> intrinsics;  // per camera (self-calibration)
  std::vector<MotionTerm> terms;
  const GcpInput* gcps = nullptr;  // optional
  std::vector<GcpTripletTerm> gcp_terms;
  bool gcp_gauge = false;  // the GCPs fix the gauge
};

std::map<uint32_t, Pose> CurrentPoses(const Unknowns& u) {
  std::map<uint32_t, Pose> poses;
  for (const auto& [id, block] : u.poses) poses[id] = block.ToPose();
  return poses;
}


MotionResidual* MakeResidual(const Unknowns& u, const MotionTerm& t) {
  std::vector<Eigen::Matrix3d> R0;
  for (const uint32_t id : t.hessian->image_ids) R0.push_back(u.poses.at(id).R0);
  return new MotionResidual(R0, t.sim, t.hessian->local_poses, t.W, t.newton_step, t.hessian->intrinsics0,
                            IntrinsicSizes(*t.hessian));
}

std::vector<double*> PoseBlocksOf(Unknowns& u, const MotionTerm& t) {
  std::vector<double*> blocks;
  for (const uint32_t id : t.hessian->image_ids) blocks.push_back(u.poses.at(id).x.data());
  return blocks;
}

std::vector<double*> IntrinsicBlocksOf(Unknowns& u, const MotionTerm& t) {
  std::vector<double*> blocks;
  for (const uint32_t id : t.hessian->intrinsic_camera_ids) blocks.push_back(u.intrinsics.at(id).x.data());
  return blocks;
}

// Fitting error e_s = |W_s (x_s - x0_s)| / unit_s at the current state.
double FittingError(const Unknowns& u, const MotionTerm& t) {
  const std::unique_ptr<MotionResidual> f(MakeResidual(u, t));
  std::vector<const double*> poses, intrinsics;
  for (const uint32_t id : t.hessian->image_ids) poses.push_back(u.poses.at(id).x.data());
  for (const uint32_t id : t.hessian->intrinsic_camera_ids) intrinsics.push_back(u.intrinsics.at(id).x.data());
  return f->Evaluate(poses, t.sim.x.data(), intrinsics).norm() / t.unit;
}

// Robust scale of the fitting errors and the IRLS weights from them; the errors in `errors`.
double Reweight(Unknowns* u, const GlobalBAOptions& options, std::vector<double>* errors = nullptr) {
  std::vector<double> e(u->terms.size());
  for (size_t i = 0; i < u->terms.size(); ++i) e[i] = FittingError(*u, u->terms[i]);
  const double sigma = UpperMedian(e);
  for (size_t i = 0; i < u->terms.size(); ++i) u->terms[i].irls_weight = IrlsWeight(e[i], sigma, options.irls_factor);
  if (errors) *errors = std::move(e);
  return sigma;
}



// Median over the terms of e_s^2 / ((6N - 7) sigma_s^2) (11 for a triplet): how far the
// solution is from each motion's model centre, in units of the motion's own noise
// (GlobalBAOptions::relinearize_misfit).
double MisfitRatio(const Unknowns& u, const std::vector<double>& errors) {
  std::vector<double> r;
  for (size_t i = 0; i < u.terms.size(); ++i) {
    const double v = NoiseVariance(*u.terms[i].hessian);
    const int informative = InformativeDimension(u.terms[i].hessian->num_views());
    if (std::isfinite(v)) r.push_back(errors[i] * errors[i] / (informative * v));
  }
  return r.empty() ? std::numeric_limits<double>::quiet_NaN() : UpperMedian(r);
}

class IterationReporter : public ceres::IterationCallback {
 public:
  IterationReporter(const Unknowns* unknowns, int round, bool report_start, GlobalBASummary* summary,
                    const GlobalBAIterationCallback* callback)
      : unknowns_(unknowns), round_(round), report_start_(report_start), summary_(summary), callback_(callback) {}

  ceres::CallbackReturnType operator()(const ceres::IterationSummary& s) override {
    // Iteration 0 of a later round repeats the previous round's end state (re-weighted), and
    // that of a re-linearised solve the previous solve's end state.
    if (s.iteration == 0 && (round_ > 0 || !report_start_)) return ceres::SOLVER_CONTINUE;
    if (s.iteration > 0) ++summary_->iterations;
    summary_->cost_per_iteration.push_back(s.cost);
    if (*callback_) {
      const std::map<uint32_t, Pose> poses = CurrentPoses(*unknowns_);
      GlobalBAIteration it;
      it.iteration = summary_->iterations;
      it.round = round_;
      it.cost = s.cost;
      it.poses = &poses;
      (*callback_)(it);
    }
    return ceres::SOLVER_CONTINUE;
  }

 private:
  const Unknowns* unknowns_;
  int round_;
  bool report_start_;
  GlobalBASummary* summary_;
  const GlobalBAIterationCallback* callback_;
};

// The reference triplet of the gauge: the one with the most points.
size_t ReferenceTerm(const Unknowns& u) {
  size_t best = 0;
  for (size_t i = 1; i < u.terms.size(); ++i)
    if (u.terms[i].hessian->num_points > u.terms[best].hessian->num_points) best = i;
  return best;
}

void FixGauge(const GlobalBAOptions& options, Unknowns* u, ceres::Problem* problem) {
  MotionTerm& ref = u->terms[ReferenceTerm(*u)];
  if (options.gauge == GaugeFixing::kFixSimilarity) {
    problem->SetParameterBlockConstant(ref.sim.x.data());
    return;
  }
  HoldPoseAndScale(&u->poses.at(ref.hessian->image_ids[0]), &u->poses.at(ref.hessian->image_ids[1]), problem);
}

// One IRLS round: Levenberg-Marquardt on the current weights. Returns the Ceres summary.
ceres::Solver::Summary SolveRound(const GlobalBAOptions& options, double sigma, int round, bool report_start,
                                  Unknowns* u, GlobalBASummary* summary, const GlobalBAIterationCallback& callback) {
  ceres::Problem::Options po;
  po.manifold_ownership = ceres::TAKE_OWNERSHIP;
  ceres::Problem problem(po);
  auto ordering = std::make_shared<ceres::ParameterBlockOrdering>();
  for (auto& [id, block] : u->poses) {
    problem.AddParameterBlock(block.x.data(), 6);
    ordering->AddElementToGroup(block.x.data(), 1);
  }
  for (auto& [id, block] : u->intrinsics) {
    problem.AddParameterBlock(block.x.data(), static_cast<int>(block.x.size()));
    // A group of their own after the poses: within a group Ceres orders by address, and the
    // intrinsics live in another array than the poses.
    ordering->AddElementToGroup(block.x.data(), 2);
  }
  for (MotionTerm& t : u->terms) {
    problem.AddParameterBlock(t.sim.x.data(), 7);
    ordering->AddElementToGroup(t.sim.x.data(), 0);  // eliminated first (Schur)
    ceres::LossFunction* huber =
        options.huber_factor > 0 && sigma > 0 ? new ceres::HuberLoss(options.huber_factor * sigma * t.unit) : nullptr;
    ceres::LossFunction* loss = new ceres::ScaledLoss(huber, t.irls_weight, ceres::TAKE_OWNERSHIP);
    std::vector<double*> blocks = PoseBlocksOf(*u, t);
    blocks.push_back(t.sim.x.data());
    for (double* k : IntrinsicBlocksOf(*u, t)) blocks.push_back(k);
    problem.AddResidualBlock(MakeResidual(*u, t), loss, blocks);
  }
  for (const GcpTripletTerm& g : u->gcp_terms) {
    MotionTerm& t = u->terms[g.term];
    ceres::LossFunction* huber =
        u->gcps->options.huber_sigmas > 0 ? new ceres::HuberLoss(u->gcps->options.huber_sigmas) : nullptr;
    problem.AddResidualBlock(GcpResidual::Create(GcpResidual(g, t.sim)),
                             new ceres::ScaledLoss(huber, g.weight, ceres::TAKE_OWNERSHIP), t.sim.x.data());
  }
  if (!u->gcp_gauge) FixGauge(options, u, &problem);

  ceres::Solver::Options so;
  so.linear_solver_type = ceres::SPARSE_SCHUR;
  so.linear_solver_ordering = ordering;
  so.max_num_iterations = options.max_iterations_per_round;
  so.function_tolerance = options.function_tolerance;
  so.parameter_tolerance = options.parameter_tolerance;
  so.initial_trust_region_radius = options.initial_trust_region_radius;
  so.num_threads = options.num_threads > 0 ? options.num_threads
                                           : std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  so.logging_type = ceres::SILENT;
  IterationReporter reporter(u, round, report_start, summary, &callback);
  so.callbacks.push_back(&reporter);
  so.update_state_every_iteration = static_cast<bool>(callback);
  ceres::Solver::Summary s;
  ceres::Solve(so, &problem, &s);
  return s;
}

// The costs of one round, whichever solver ran it.
struct RoundSummary {
  bool failed = false;
  std::string message;
  double initial_cost = 0.0, final_cost = 0.0;
  int iterations = 0;
  Eigen::MatrixXd intrinsics_inverse_hessian;  // block solver only (MotionBlockSummary)
  double final_radius = 0.0;                   // block solver only
};

// Whether a round can run on the motion-block normal equations (motion_normal_equations.h):
// no robust loss on the motions, no GCP residuals, the gauge held by a pose and a scale.
bool BlockSolverApplies(const GlobalBAOptions& options, double sigma, const Unknowns& u) {
  return !(options.huber_factor > 0 && sigma > 0) && u.gcp_terms.empty() && !u.gcp_gauge &&
         options.gauge == GaugeFixing::kFixPoseAndScale;
}

RoundSummary SolveRoundByBlocks(const GlobalBAOptions& options, int round, bool report_start, Unknowns* u,
                                GlobalBASummary* summary, const GlobalBAIterationCallback& callback) {
  MotionBlockProblem problem;
  std::map<uint32_t, int> index, intrinsic_index;
  for (auto& [id, block] : u->poses) {
    index[id] = static_cast<int>(problem.poses.size());
    problem.poses.push_back(&block);
  }
  // The solver works on Eigen::VectorXd: copies, written back after the solve.
  std::vector<Eigen::VectorXd> intrinsics;
  intrinsics.reserve(u->intrinsics.size());
  for (auto& [id, block] : u->intrinsics) {
    intrinsic_index[id] = static_cast<int>(intrinsics.size());
    intrinsics.emplace_back(block.x);
  }
  for (Eigen::VectorXd& k : intrinsics) problem.intrinsics.push_back(&k);
  std::vector<std::unique_ptr<MotionResidual>> residuals;
  std::vector<Eigen::MatrixXd> scalar_h;
  scalar_h.reserve(u->terms.size());  // stable addresses
  for (MotionTerm& t : u->terms) {
    residuals.emplace_back(MakeResidual(*u, t));
    MotionBlockTerm term;
    term.residual = residuals.back().get();
    // W^T W: the local Hessian itself for the pointless BA (W = D V), formed for Aver_BA.
    if (options.weighting == TripletWeighting::kHessian) {
      term.h = &t.hessian->h;
    } else {
      scalar_h.push_back(t.W.Gram());
      term.h = &scalar_h.back();
    }
    for (const uint32_t id : t.hessian->image_ids) term.poses.push_back(index.at(id));
    for (const uint32_t id : t.hessian->intrinsic_camera_ids) term.intrinsics.push_back(intrinsic_index.at(id));
    term.sim = t.sim.x.data();
    term.weight = t.irls_weight;
    problem.terms.push_back(std::move(term));
  }
  const MotionTerm& ref = u->terms[ReferenceTerm(*u)];
  const uint32_t a = ref.hessian->image_ids[0], b = ref.hessian->image_ids[1];
  problem.fixed_pose = index.at(a);
  problem.scale_pose = index.at(b);
  (u->poses.at(b).x.head<3>() - u->poses.at(a).x.head<3>()).cwiseAbs().maxCoeff(&problem.scale_coord);

  MotionBlockSolverOptions so;
  so.max_iterations = options.max_iterations_per_round;
  so.function_tolerance = options.function_tolerance;
  so.parameter_tolerance = options.parameter_tolerance;
  so.initial_radius = options.initial_trust_region_radius;
  so.embedded_similarity_iterations = options.embedded_similarity_iterations;
  const MotionBlockCallback report = [&](int iteration, double cost) {
    if (iteration == 0 && (round > 0 || !report_start)) return;
    if (iteration > 0) ++summary->iterations;
    summary->cost_per_iteration.push_back(cost);
    if (callback) {
      const std::map<uint32_t, Pose> poses = CurrentPoses(*u);
      GlobalBAIteration it;
      it.iteration = summary->iterations;
      it.round = round;
      it.cost = cost;
      it.poses = &poses;
      callback(it);
    }
  };
  const MotionBlockSummary s = SolveMotionBlocks(problem, so, report);
  for (auto& [id, block] : u->intrinsics) block.x = intrinsics[intrinsic_index.at(id)];
  RoundSummary out{!s.usable, s.message, s.initial_cost, s.final_cost, s.iterations};
  out.intrinsics_inverse_hessian = s.intrinsics_inverse_hessian;
  out.final_radius = s.final_radius;
  return out;
}

RoundSummary SolveRoundByCeres(const GlobalBAOptions& options, double sigma, int round, bool report_start,
                               Unknowns* u, GlobalBASummary* summary, const GlobalBAIterationCallback& callback) {
  const ceres::Solver::Summary s = SolveRound(options, sigma, round, report_start, u, summary, callback);
  return {s.termination_type == ceres::FAILURE, s.message, s.initial_cost, s.final_cost,
          static_cast<int>(s.iterations.size()) - 1};
}

// The global intrinsic unknowns of the cameras of `h` not yet in `u`, started at h's values
// (every motion of a camera carries the same free set, the one intrinsics.h selected).
void AddIntrinsicUnknowns(const LocalHessian& h, Unknowns* u) {
  for (size_t c = 0, offset = 0; c < h.intrinsic_camera_ids.size(); offset += h.intrinsic_free[c].size(), ++c) {
    const uint32_t id = h.intrinsic_camera_ids[c];
    if (u->intrinsics.count(id)) {
      if (u->intrinsics.at(id).free != h.intrinsic_free[c])
        throw InputError("global BA: the local hessians hold different intrinsic unknowns for camera " +
                         std::to_string(id));
      continue;
    }
    IntrinsicsBlock& block = u->intrinsics[id];
    block.free = h.intrinsic_free[c];
    block.x = h.intrinsics0.segment(offset, block.free.size());
  }
}

// Per-coordinate pixel noise variance pooled over the motions (their local BA residuals).
double PooledNoiseVariance(const Unknowns& u) {
  double sum = 0.0, dof = 0.0;
  for (const MotionTerm& t : u.terms) {
    const LocalHessian& h = *t.hessian;
    const double d = ResidualDegreesOfFreedom(h);
    if (d > 0 && std::isfinite(h.rms_px)) {
      sum += h.rms_px * h.rms_px * h.num_observations;
      dof += d;
    }
  }
  return dof > 0 ? sum / dof : std::numeric_limits<double>::quiet_NaN();
}

std::map<uint32_t, GlobalIntrinsics> ResultIntrinsics(const Unknowns& u, const std::map<uint32_t, Eigen::VectorXd>& initial,
                                                      const Eigen::MatrixXd& inverse_hessian) {
  std::map<uint32_t, GlobalIntrinsics> out;
  const double variance = PooledNoiseVariance(u);
  int row = 0;
  for (const auto& [id, block] : u.intrinsics) {
    GlobalIntrinsics& g = out[id];
    g.free = block.free;
    g.initial = initial.at(id);
    g.values = block.x;
    g.stddev = Eigen::VectorXd::Constant(block.x.size(), std::numeric_limits<double>::quiet_NaN());
    for (int i = 0; i < block.x.size(); ++i, ++row)
      if (inverse_hessian.rows() > row) g.stddev(i) = std::sqrt(std::max(0.0, inverse_hessian(row, row)) * variance);
  }
  return out;
}

}  // namespace

GlobalBAResult internal::RunGlobalBA(const std::map<uint32_t, Pose>& initial_poses,
                                     const std::vector<LocalMotion>& motions,
                                     const std::vector<LocalHessian>& hessians, const GlobalBAOptions& options,
                                     const GlobalBAIterationCallback& callback, const GcpInput* gcps,
                                     bool report_start) {
  Timer timer;
  const MotionSelection sel = SelectMotions(initial_poses, motions, hessians);
  if (sel.hessian_indices.empty())
    throw InputError("global BA: no usable motion (" + std::to_string(hessians.size()) +
                     " local hessians, none ok with initial poses for all its images)");

  Unknowns u;
  for (uint32_t id : sel.images) u.poses[id] = PoseBlock::FromPose(initial_poses.at(id));
  for (int hi : sel.hessian_indices) {
    MotionTerm t;
    t.hessian = &hessians[hi];
    t.W = MotionWeightOf(*t.hessian, options);
    // Aver_BA averages the relative motions themselves (scalar weights, no quadratic model).
    if (options.weighting == TripletWeighting::kHessian) t.newton_step = t.hessian->newton_step;
    t.unit = ResidualUnit(*t.hessian, options);
    std::vector<Pose> global;
    for (const uint32_t id : t.hessian->image_ids) global.push_back(initial_poses.at(id));
    const LocalMotion& motion = motions[t.hessian->motion_index];
    t.sim = options.similarity_init == SimilarityInit::kFromPoses
                ? InitializeSimilarity(global, t.hessian->local_poses, motion.global_to_local)
                : SimilarityFromSim3(global, motion.global_to_local);
    AddIntrinsicUnknowns(*t.hessian, &u);
    u.terms.push_back(std::move(t));
  }
  if (gcps && !gcps->gcps.empty()) {
    std::vector<const LocalHessian*> used;
    for (const MotionTerm& t : u.terms) used.push_back(t.hessian);
    u.gcps = gcps;
    u.gcp_terms = BuildGcpTerms(*gcps, used);
    u.gcp_gauge = GcpTermsFixGauge(*gcps, u.gcp_terms);
    if (!u.gcp_gauge)
      PGBA_LOG_WARN << "global BA: fewer than 3 non-collinear GCPs seen in triplets; the gauge stays fixed by a "
                       "triplet and the GCPs only act through the frame transfer and their residuals";
  }

  GlobalBAResult result;
  GlobalBASummary& summary = result.summary;
  summary.num_poses = static_cast<int>(u.poses.size());
  summary.num_triplets = static_cast<int>(u.terms.size());
  summary.num_params = 6 * summary.num_poses + 7 * summary.num_triplets;
  for (const auto& [id, block] : u.intrinsics) summary.num_params += static_cast<int>(block.x.size());
  Eigen::MatrixXd intrinsics_inverse_hessian;
  std::map<uint32_t, Eigen::VectorXd> initial_intrinsics;
  for (const auto& [id, block] : u.intrinsics) initial_intrinsics[id] = block.x;
  summary.num_triplets_excluded = sel.num_excluded;
  summary.excluded_images = sel.excluded_images;
  summary.num_gcp_residuals = static_cast<int>(u.gcp_terms.size());
  summary.gcp_gauge = u.gcp_gauge;
  if (sel.num_excluded > 0 || !sel.excluded_images.empty())
    PGBA_LOG_WARN << "global BA: " << sel.num_excluded << " motions and " << sel.excluded_images.size()
                  << " images excluded (no usable local hessian, no initial pose, or outside the largest "
                     "rigidly connected component of the motions)";

  for (int round = 0; round < std::max(1, options.max_rounds); ++round) {
    const double sigma = Reweight(&u, options);
    const RoundSummary s = BlockSolverApplies(options, sigma, u)
                               ? SolveRoundByBlocks(options, round, report_start, &u, &summary, callback)
                               : SolveRoundByCeres(options, sigma, round, report_start, &u, &summary, callback);
    if (round == 0) summary.initial_cost = s.initial_cost;
    summary.final_cost = s.final_cost;
    intrinsics_inverse_hessian = s.intrinsics_inverse_hessian;
    summary.final_trust_region_radius = s.final_radius;
    summary.rounds = round + 1;
    for (auto& [id, block] : u.poses) block.Relinearize();
    for (MotionTerm& t : u.terms) t.sim.Relinearize();
    PGBA_LOG_DEBUG << "global BA round " << round << ": sigma " << sigma << ", cost " << s.initial_cost << " -> "
                   << s.final_cost << " in " << s.iterations << " iterations";
    if (s.failed) throw InputError("global BA: solver failure: " + s.message);
    const double decrease = s.initial_cost > 0 ? (s.initial_cost - s.final_cost) / s.initial_cost : 0.0;
    if (round > 0 && decrease < options.round_tolerance) break;
  }
  std::vector<double> errors;
  summary.robust_scale = Reweight(&u, options, &errors);
  if (options.weighting == TripletWeighting::kHessian) summary.misfit_ratio = MisfitRatio(u, errors);
  summary.misfit_ratio_initial = summary.misfit_ratio;

  result.poses = CurrentPoses(u);
  result.intrinsics = ResultIntrinsics(u, initial_intrinsics, intrinsics_inverse_hessian);
  result.similarities.assign(motions.size(), Sim3());
  result.irls_weights.assign(motions.size(), 0.0);
  for (const MotionTerm& t : u.terms) {
    result.similarities[t.hessian->motion_index] = t.sim.ToSim3();
    result.irls_weights[t.hessian->motion_index] = t.irls_weight;
    summary.num_triplets_downweighted += t.irls_weight < 0.5;
  }
  summary.seconds = timer.Seconds();
  PGBA_LOG_INFO << "global BA (" << (options.weighting == TripletWeighting::kHessian ? "pointless" : "averaging")
                << "): " << summary.num_poses << " poses, " << summary.num_triplets << " motions, "
                << summary.iterations << " iterations in " << summary.rounds << " rounds, " << summary.seconds
                << " s, fitting scale " << summary.robust_scale << ", " << summary.num_triplets_downweighted
                << " motions down-weighted"
                << (std::isfinite(summary.misfit_ratio) ? ", misfit " + std::to_string(summary.misfit_ratio) : "");
  return result;
}

GlobalBAResult PointlessGlobalBA(const std::map<uint32_t, Pose>& initial_poses, const std::vector<LocalMotion>& motions,
                                 const std::vector<LocalHessian>& hessians, const GlobalBAOptions& options,
                                 const GlobalBAIterationCallback& callback, const GcpInput* gcps) {
  return internal::RunGlobalBA(initial_poses, motions, hessians, options, callback, gcps);
}

GlobalBAResult AveragingGlobalBA(const std::map<uint32_t, Pose>& initial_poses, const std::vector<LocalMotion>& motions,
                                 const std::vector<LocalHessian>& hessians, const GlobalBAOptions& options,
                                 const GlobalBAIterationCallback& callback, const GcpInput* gcps) {
  GlobalBAOptions scalar = options;
  scalar.weighting = TripletWeighting::kScalar;
  return internal::RunGlobalBA(initial_poses, motions, hessians, scalar, callback, gcps);
}

}  // namespace pgba
