#include "modules/global_ba/global_ba_rounds.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <memory>
#include <vector>

#include "modules/global_ba/gcp_residual.h"
#include "modules/global_ba/motion_normal_equations.h"
#include "pgba/optim/ceres_solver_options.h"
#include "pgba/optim/loss_function_options.h"

namespace pgba::internal {

namespace {

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
        options.huber_factor > 0 && sigma > 0
            ? LossFunctionOptions{LossType::kHuber, options.huber_factor * sigma * t.unit}.CreateLossFunction()
            : nullptr;
    ceres::LossFunction* loss = new ceres::ScaledLoss(huber, t.irls_weight, ceres::TAKE_OWNERSHIP);
    std::vector<double*> blocks = PoseBlocksOf(*u, t);
    blocks.push_back(t.sim.x.data());
    for (double* k : IntrinsicBlocksOf(*u, t)) blocks.push_back(k);
    problem.AddResidualBlock(MakeResidual(*u, t), loss, blocks);
  }
  for (const GcpTripletTerm& g : u->gcp_terms) {
    MotionTerm& t = u->terms[g.term];
    ceres::LossFunction* huber = u->gcps->options.huber_sigmas > 0
                                     ? LossFunctionOptions{LossType::kHuber, u->gcps->options.huber_sigmas}.CreateLossFunction()
                                     : nullptr;
    problem.AddResidualBlock(GcpResidual::Create(GcpResidual(g, t.sim)),
                             new ceres::ScaledLoss(huber, g.weight, ceres::TAKE_OWNERSHIP), t.sim.x.data());
  }
  if (!u->gcp_gauge) FixGauge(options, u, &problem);

  ceres::Solver::Options so = CeresSolverOptions(options.solver);
  so.linear_solver_ordering = ordering;
  IterationReporter reporter(u, round, report_start, summary, &callback);
  so.callbacks.push_back(&reporter);
  so.update_state_every_iteration = static_cast<bool>(callback);
  ceres::Solver::Summary s;
  ceres::Solve(so, &problem, &s);
  return s;
}

}  // namespace

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
  std::vector<SymmetricMatrix> scalar_h;
  scalar_h.reserve(u->terms.size());  // stable addresses
  for (MotionTerm& t : u->terms) {
    residuals.emplace_back(MakeResidual(*u, t));
    MotionBlockTerm term;
    term.residual = residuals.back().get();
    // W^T W: the local Hessian itself for the pointless BA (W = D V), formed for Aver_BA.
    if (options.weighting == TripletWeighting::kHessian) {
      term.h = &t.hessian->h;
    } else {
      scalar_h.emplace_back(t.W.Gram());
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
  const MotionBlockSummary s = SolveMotionBlocks(problem, options.solver, report);
  for (auto& [id, block] : u->intrinsics) block.x = intrinsics[intrinsic_index.at(id)];
  return {!s.usable, s.message, s.initial_cost, s.final_cost, s.iterations, s.intrinsics_inverse_hessian,
          s.final_radius};
}

RoundSummary SolveRoundByCeres(const GlobalBAOptions& options, double sigma, int round, bool report_start,
                               Unknowns* u, GlobalBASummary* summary, const GlobalBAIterationCallback& callback) {
  const ceres::Solver::Summary s = SolveRound(options, sigma, round, report_start, u, summary, callback);
  return {s.termination_type == ceres::FAILURE,
          s.message,
          s.initial_cost,
          s.final_cost,
          static_cast<int>(s.iterations.size()) - 1,
          Eigen::MatrixXd(),  // no intrinsics covariance from this path
          0.0};
}

}  // namespace pgba::internal
