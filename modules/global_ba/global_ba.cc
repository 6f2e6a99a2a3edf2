#include "modules/global_ba/global_ba.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <vector>

#include "pgba/io/option_ranges.h"
#include "modules/global_ba/gcp_terms.h"
#include "modules/global_ba/global_ba_rounds.h"
#include "modules/global_ba/global_ba_solve.h"
#include "modules/global_ba/global_ba_unknowns.h"
#include "modules/global_ba/motion_residual.h"
#include "modules/global_ba/motion_selection.h"
#include "modules/global_ba/motion_similarity.h"
#include "modules/global_ba/motion_weighting.h"
#include "pgba/optim/pose_parameterization.h"
#include "pgba/util/error.h"
#include "pgba/util/logging.h"
#include "pgba/util/timer.h"
#include "pgba/util/upper_median.h"

namespace pgba {

using internal::BlockSolverApplies;
using internal::CurrentPoses;
using internal::IntrinsicSizes;
using internal::IntrinsicsBlock;
using internal::MakeResidual;
using internal::MotionTerm;
using internal::NoiseVariance;
using internal::ResidualDegreesOfFreedom;
using internal::RoundSummary;
using internal::SolveRoundByBlocks;
using internal::SolveRoundByCeres;
using internal::Unknowns;

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

// Fitting error e_s = |W_s (x_s - x0_s)| / unit_s at the current state.
double FittingError(const Unknowns& u, const MotionTerm& t) {
  const std::unique_ptr<MotionResidual> f(MakeResidual(u, t));
  std::vector<const double*> poses, intrinsics;
  for (const uint32_t id : t.hessian->image_ids) poses.push_back(u.poses.at(id).x.data());
  for (const uint32_t id : t.hessian->intrinsic_camera_ids) intrinsics.push_back(u.intrinsics.at(id).x.data());
  return std::sqrt(f->SquaredNorm(poses, t.sim.x.data(), intrinsics)) / t.unit;
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
  // The Ceres solver needs residual vectors, so W factored; the motion-block solver only h.
  const bool factored = !BlockSolverApplies(options, 0.0, u) || options.huber_factor > 0;
  for (MotionTerm& t : u.terms) t.W = MotionWeightOf(*t.hessian, options, factored);

  GlobalBAResult result;
  GlobalBASummary& summary = result.summary;
  summary.num_poses = static_cast<int>(u.poses.size());
  summary.num_motions = static_cast<int>(u.terms.size());
  summary.num_params = 6 * summary.num_poses + 7 * summary.num_motions;
  for (const auto& [id, block] : u.intrinsics) summary.num_params += static_cast<int>(block.x.size());
  Eigen::MatrixXd intrinsics_inverse_hessian;
  std::map<uint32_t, Eigen::VectorXd> initial_intrinsics;
  for (const auto& [id, block] : u.intrinsics) initial_intrinsics[id] = block.x;
  summary.num_motions_excluded = sel.num_excluded;
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
    summary.num_motions_downweighted += t.irls_weight < 0.5;
  }
  summary.seconds = timer.Seconds();
  PGBA_LOG_DEBUG << "global BA (" << (options.weighting == TripletWeighting::kHessian ? "pointless" : "averaging")
                << "): " << summary.num_poses << " poses, " << summary.num_motions << " motions, "
                << summary.iterations << " iterations in " << summary.rounds << " rounds, " << summary.seconds
                << " s, fitting scale " << summary.robust_scale << ", " << summary.num_motions_downweighted
                << " motions down-weighted"
                << (std::isfinite(summary.misfit_ratio) ? ", misfit " + std::to_string(summary.misfit_ratio) : "");
  return result;
}

GlobalBAOptions PaperTripletGlobalBAOptions() {
  GlobalBAOptions o;
  o.irls_factor = 3.0;
  o.huber_factor = 3.0;
  o.max_rounds = 4;
  o.relinearize_checked = false;
  o.relinearize_misfit = 0.5;
  o.relinearize_tolerance = 0.5;
  o.max_relinearizations = 3;
  return o;
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

std::string GlobalBAOptions::Check() const {
  if (const std::string m = CheckRanges(*this, "global_ba"); !m.empty()) return m;
  return "";
}

}  // namespace pgba
