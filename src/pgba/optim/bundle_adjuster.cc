#include "pgba/optim/bundle_adjuster.h"

#include <ceres/ceres.h>
#include <ceres/product_manifold.h>
#include <ceres/sphere_manifold.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <stdexcept>
#include <thread>

#include "pgba/io/option_ranges.h"
#include "pgba/optim/ceres_solver_options.h"
#include "pgba/optim/pose_parameterization.h"
#include "pgba/util/timer.h"

namespace pgba {

namespace {

// Points x with |x - c| = const: Ceres' sphere manifold translated to centre c. Used on the
// centre of the gauge's scale image so that the anchor-scale distance stays fixed.
class OffsetSphereManifold final : public ceres::Manifold {
 public:
  explicit OffsetSphereManifold(const Eigen::Vector3d& c) : c_(c) {}
  int AmbientSize() const override { return 3; }
  int TangentSize() const override { return 2; }
  bool Plus(const double* x, const double* delta, double* x_plus_delta) const override {
    const Eigen::Vector3d y = Eigen::Map<const Eigen::Vector3d>(x) - c_;
    Eigen::Map<Eigen::Vector3d> out(x_plus_delta);
    if (!sphere_.Plus(y.data(), delta, out.data())) return false;
    out += c_;
    return true;
  }
  bool PlusJacobian(const double* x, double* jacobian) const override {
    const Eigen::Vector3d y = Eigen::Map<const Eigen::Vector3d>(x) - c_;
    return sphere_.PlusJacobian(y.data(), jacobian);
  }
  bool Minus(const double* y, const double* x, double* y_minus_x) const override {
    const Eigen::Vector3d a = Eigen::Map<const Eigen::Vector3d>(y) - c_;
    const Eigen::Vector3d b = Eigen::Map<const Eigen::Vector3d>(x) - c_;
    return sphere_.Minus(a.data(), b.data(), y_minus_x);
  }
  bool MinusJacobian(const double* x, double* jacobian) const override {
    const Eigen::Vector3d y = Eigen::Map<const Eigen::Vector3d>(x) - c_;
    return sphere_.MinusJacobian(y.data(), jacobian);
  }

 private:
  Eigen::Vector3d c_;
  ceres::SphereManifold<3> sphere_;
};

ceres::LinearSolverType ChooseLinearSolver(const BundleAdjusterOptions& o, int free_poses, bool constant_points) {
  // Without free points there is nothing to eliminate: a pose-only problem.
  if (constant_points) return free_poses <= o.dense_schur_max_poses ? ceres::DENSE_QR : ceres::SPARSE_NORMAL_CHOLESKY;
  // Only points free: independent 3x3 blocks, no reduced camera system to form.
  if (free_poses == 0) return ceres::SPARSE_NORMAL_CHOLESKY;
  if (o.linear_solver == "auto") return free_poses <= o.dense_schur_max_poses ? ceres::DENSE_SCHUR : ceres::SPARSE_SCHUR;
  if (o.linear_solver == "dense_schur") return ceres::DENSE_SCHUR;
  if (o.linear_solver == "sparse_schur") return ceres::SPARSE_SCHUR;
  if (o.linear_solver == "iterative_schur") return ceres::ITERATIVE_SCHUR;
  throw std::invalid_argument("unknown bundle adjuster linear_solver '" + o.linear_solver +
                              "' (auto, dense_schur, sparse_schur, iterative_schur)");
}

// Copies the pose blocks into the reconstruction (for callbacks and the final result).
void WritePoses(const std::map<uint32_t, PoseBlock>& blocks, Reconstruction* rec) {
  for (const auto& [id, b] : blocks) rec->images.at(id).pose = b.ToPose();
}

class CallbackAdapter : public ceres::IterationCallback {
 public:
  CallbackAdapter(const BundleAdjustmentProblem& p, const std::map<uint32_t, PoseBlock>& blocks, Reconstruction* rec)
      : problem_(p), blocks_(blocks), rec_(rec) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary& s) override {
    WritePoses(blocks_, rec_);
    BundleAdjustmentIteration it;
    it.iteration = s.iteration;
    it.cost = s.cost;
    it.step_accepted = s.step_is_successful;
    it.state = rec_;
    problem_.callback(it);
    return ceres::SOLVER_CONTINUE;
  }

 private:
  const BundleAdjustmentProblem& problem_;
  const std::map<uint32_t, PoseBlock>& blocks_;
  Reconstruction* rec_;
};

}  // namespace

nlohmann::json ToJson(const BundleAdjustmentSummary& s) {
  return {{"usable", s.usable},
          {"converged", s.converged},
          {"iterations", s.iterations},
          {"initial_cost", s.initial_cost},
          {"final_cost", s.final_cost},
          {"seconds", s.seconds},
          {"num_free_poses", s.num_free_poses},
          {"num_points", s.num_points},
          {"num_observations", s.num_observations},
          {"num_free_intrinsics", s.num_free_intrinsics},
          {"linear_solver", s.linear_solver},
          {"message", s.message}};
}

// Its ranges and names are those of its config sections (point_based.bundle, triplets.bundle_adjuster).
std::string BundleAdjusterOptions::Check() const { return CheckRanges(*this, "point_based.bundle"); }

BundleAdjustmentSummary BundleAdjust(const BundleAdjustmentProblem& problem, const BundleAdjusterOptions& options,
                                     Reconstruction* rec) {
  if (const std::string invalid = options.Check(); !invalid.empty())
    throw std::invalid_argument("bundle adjuster options: " + invalid);
  Timer timer;
  BundleAdjustmentSummary summary;
  const std::set<uint32_t> images(problem.image_ids.begin(), problem.image_ids.end());
  const std::set<uint32_t> constant(problem.constant_pose_ids.begin(), problem.constant_pose_ids.end());
  auto participates = [&](uint32_t id) { return images.empty() || images.count(id) > 0; };

  std::vector<uint64_t> track_ids = problem.track_ids;
  if (track_ids.empty())
    for (const auto& [id, p] : rec->points3D) track_ids.push_back(id);

  ceres::Problem::Options problem_options;
  problem_options.loss_function_ownership = ceres::TAKE_OWNERSHIP;
  ceres::Problem ceres_problem(problem_options);
  ceres::LossFunction* loss = options.loss.CreateLossFunction();  // shared by every residual; owned by the problem
  std::map<uint32_t, PoseBlock> blocks;
  std::vector<double*> point_blocks;
  // The estimated cameras' parameters (copies, written back after the solve).
  std::map<uint32_t, std::vector<double>> intrinsics;
  for (const auto& [id, free] : problem.free_intrinsics)
    if (rec->cameras.count(id)) intrinsics[id] = rec->cameras.at(id).params;

  for (uint64_t pid : track_ids) {
    auto it = rec->points3D.find(pid);
    if (it == rec->points3D.end()) continue;
    Point3D& point = it->second;
    bool any = false;
    for (const TrackElement& el : point.track) {
      if (!participates(el.image_id)) continue;
      const Image& image = rec->images.at(el.image_id);
      auto [bit, inserted] = blocks.try_emplace(el.image_id);
      if (inserted) bit->second = PoseBlock::FromPose(image.pose);
      const Eigen::Vector2d& xy = image.points2D.at(el.point2D_idx).xy;
      if (auto k = intrinsics.find(image.camera_id); k != intrinsics.end()) {
        ceres_problem.AddResidualBlock(
            CreateReprojectionErrorWithIntrinsics(rec->CameraOf(image).model, bit->second.R0, xy), loss,
            bit->second.x.data(), point.xyz.data(), k->second.data());
      } else {
        ceres_problem.AddResidualBlock(ReprojectionError::Create(&rec->CameraOf(image), bit->second.R0, xy), loss,
                                       bit->second.x.data(), point.xyz.data());
      }
      ++summary.num_observations;
      any = true;
    }
    if (any) {
      point_blocks.push_back(point.xyz.data());
      if (problem.constant_points) ceres_problem.SetParameterBlockConstant(point.xyz.data());
    }
  }
  if (summary.num_observations == 0) {
    if (loss) delete loss;
    summary.message = "no observations";
    return summary;
  }
  summary.num_points = static_cast<int>(point_blocks.size());
  for (auto& [id, params] : intrinsics) {
    if (!ceres_problem.HasParameterBlock(params.data())) continue;  // no participating image
    const std::vector<int>& free = problem.free_intrinsics.at(id);
    if (ceres::Manifold* m = IntrinsicsManifold(rec->cameras.at(id), free))
      ceres_problem.SetManifold(params.data(), m);
    summary.num_free_intrinsics += static_cast<int>(free.size());
  }

  for (auto& [id, b] : blocks) {
    if (constant.count(id) || (problem.fix_gauge && id == problem.gauge_anchor)) {
      ceres_problem.SetParameterBlockConstant(b.x.data());
    } else {
      ++summary.num_free_poses;
    }
  }
  if (problem.fix_gauge) {
    auto a = blocks.find(problem.gauge_anchor);
    auto s = blocks.find(problem.gauge_scale);
    if (a == blocks.end() || s == blocks.end() || problem.gauge_anchor == problem.gauge_scale)
      throw std::invalid_argument("bundle adjuster gauge images must be two distinct participating images");
    if (!constant.count(problem.gauge_scale)) {
      ceres_problem.SetManifold(s->second.x.data(),
                                new ceres::ProductManifold<OffsetSphereManifold, ceres::EuclideanManifold<3>>(
                                    OffsetSphereManifold(a->second.x.head<3>()), ceres::EuclideanManifold<3>()));
    }
  }

  SolverOptions solver_options = options.solver;
  solver_options.linear_solver_type = ChooseLinearSolver(options, summary.num_free_poses, problem.constant_points);
  // No explicit ordering for the Schur solvers: Ceres then picks the eliminated blocks as a
  // maximal independent set in the order the blocks were added (ComputeStableSchurOrdering:
  // the points, each seen by few poses), deterministic. An explicit ParameterBlockOrdering
  // orders each group by address, and the addresses of map nodes (the points of *rec, the
  // pose blocks) depend on the heap's history, hence on the thread that ran the adjustment:
  // the last bits of every triplet then changed with the thread count.
  ceres::Solver::Options solver = CeresSolverOptions(solver_options);
  std::unique_ptr<CallbackAdapter> callback;
  if (problem.callback) {
    callback = std::make_unique<CallbackAdapter>(problem, blocks, rec);
    solver.callbacks.push_back(callback.get());
    solver.update_state_every_iteration = true;
  }

  ceres::Solver::Summary ceres_summary;
  ceres::Solve(solver, &ceres_problem, &ceres_summary);
  WritePoses(blocks, rec);
  for (const auto& [id, params] : intrinsics) rec->cameras.at(id).params = params;

  summary.usable = ceres_summary.IsSolutionUsable();
  summary.converged = ceres_summary.termination_type == ceres::CONVERGENCE;
  summary.iterations = static_cast<int>(ceres_summary.iterations.size()) - 1;  // iteration 0 is the start
  summary.initial_cost = ceres_summary.initial_cost;
  summary.final_cost = ceres_summary.final_cost;
  summary.linear_solver = ceres::LinearSolverTypeToString(ceres_summary.linear_solver_type_used);
  summary.message = ceres_summary.message;
  summary.seconds = timer.Seconds();
  return summary;
}

void ChooseGauge(const Reconstruction& rec, BundleAdjustmentProblem* problem) {
  std::vector<uint32_t> ids = problem->image_ids;
  if (ids.empty())
    for (const auto& [id, im] : rec.images) ids.push_back(id);
  if (ids.size() < 2) return;
  const uint32_t anchor = ids.front();
  const Eigen::Vector3d ca = rec.images.at(anchor).pose.C();
  double best = -1.0;
  uint32_t scale = ids[1];
  for (uint32_t id : ids) {
    const double d = (rec.images.at(id).pose.C() - ca).norm();
    if (id != anchor && d > best) {
      best = d;
      scale = id;
    }
  }
  problem->fix_gauge = true;
  problem->gauge_anchor = anchor;
  problem->gauge_scale = scale;
}

std::vector<double> ObservationErrorsPx(const Reconstruction& rec, uint64_t point3D_id) {
  const Point3D& p = rec.points3D.at(point3D_id);
  std::vector<double> errors;
  errors.reserve(p.track.size());
  for (const TrackElement& el : p.track) {
    const Image& image = rec.images.at(el.image_id);
    const Eigen::Vector3d xc = image.pose.ToCamera(p.xyz);
    errors.push_back(xc.z() > 0 ? (rec.CameraOf(image).Project(xc) - image.points2D.at(el.point2D_idx).xy).norm()
                                : std::numeric_limits<double>::infinity());
  }
  return errors;
}

size_t FilterObservations(double max_px, Reconstruction* rec) {
  size_t removed = 0;
  std::vector<uint64_t> emptied;
  for (auto& [pid, point] : rec->points3D) {
    const std::vector<double> errors = ObservationErrorsPx(*rec, pid);
    std::vector<TrackElement> kept;
    for (size_t i = 0; i < point.track.size(); ++i) {
      if (errors[i] <= max_px) {
        kept.push_back(point.track[i]);
      } else {
        rec->images.at(point.track[i].image_id).points2D[point.track[i].point2D_idx].point3D_id = kNoPoint3D;
        ++removed;
      }
    }
    point.track = std::move(kept);
    if (point.track.size() < 2) emptied.push_back(pid);
  }
  for (uint64_t pid : emptied) rec->DeletePoint3D(pid);
  return removed;
}

}  // namespace pgba
