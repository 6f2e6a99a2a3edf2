#include "modules/local_hessian/local_bundle.h"

#include <ceres/ceres.h>
#include <ceres/jet.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>

#include "pgba/io/option_ranges.h"
#include "pgba/geometry/triangulation.h"
#include "pgba/optim/ceres_solver_options.h"

namespace pgba {

double AttenuationWeight(int num_points, double q) {
  if (!(q > 0) || std::isinf(q) || num_points <= 0) return 1.0;
  const double m = num_points;
  const double gamma = m * q / (m + q);
  return gamma / m;
}

namespace {

// Gauss-Newton iterations of MovePointsToLossMinimum (a point's 3x3 problem: most stop on the
// cost test after a few).
constexpr int kLossMinimumIterations = 10;

// Pose prior of the local BA: A (x - x_in) over the N pose blocks, A^T A = prior. Linear in
// the poses, so its Jacobian is A itself.
class PosePriorCost : public ceres::CostFunction {
 public:
  PosePriorCost(const Eigen::MatrixXd& sqrt_prior, const Eigen::VectorXd& center) : A_(sqrt_prior), center_(center) {
    set_num_residuals(static_cast<int>(A_.rows()));
    for (int k = 0; k < A_.cols() / 6; ++k) mutable_parameter_block_sizes()->push_back(6);
  }
  bool Evaluate(double const* const* poses, double* residuals, double** jacobians) const override {
    const int n = static_cast<int>(A_.cols());
    Eigen::VectorXd d(n);
    for (int k = 0; k < n / 6; ++k)
      for (int i = 0; i < 6; ++i) d(6 * k + i) = poses[k][i] - center_(6 * k + i);
    Eigen::Map<Eigen::VectorXd>(residuals, n) = A_ * d;
    if (jacobians)
      for (int k = 0; k < n / 6; ++k)
        if (jacobians[k])
          Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, 6, Eigen::RowMajor>>(jacobians[k], n, 6) =
              A_.middleCols<6>(6 * k);
    return true;
  }

 private:
  Eigen::MatrixXd A_;
  Eigen::VectorXd center_;
};

// Each point moved to the minimum of the problem's loss over its kept observations, poses
// and intrinsics held: Gauss-Newton with the loss's IRLS weights rho'(s), a step kept only if
// it lowers the point's cost. The triangulation's point is the Huber estimate over the views
// within max_reprojection_px, which is that minimum only for the Huber loss; under another
// loss (Cauchy over every view up to cauchy_max_reprojection_px) h's Schur complement and
// RobustCost must be taken where the loss puts the point, as the point-based BA's are, or
// the true cost of a step disagrees with what its models predicted.
void MovePointsToLossMinimum(LocalBundleProblem* p, int max_iterations) {
  const std::unique_ptr<ceres::LossFunction> loss(p->loss.CreateLossFunction());
  using Jet3 = ceres::Jet<double, 3>;
  const auto rho = [&loss](double s, double out[3]) {
    out[0] = s, out[1] = 1.0, out[2] = 0.0;
    if (loss) loss->Evaluate(s, out);
  };
  std::vector<Jet3> pose(6);
  size_t begin = 0;
  while (begin < p->observations.size()) {
    size_t end = begin;
    while (end < p->observations.size() && p->observations[end].point == p->observations[begin].point) ++end;
    Eigen::Vector3d& X = p->points[p->observations[begin].point];
    const auto cost_at = [&](const Eigen::Vector3d& Y) {
      double c = 0.0;
      for (size_t i = begin; i < end; ++i) {
        const LocalObservation& o = p->observations[i];
        double r[2], f[3];
        ReprojectionError(&p->CameraOf(o.view), p->poses[o.view].R0, o.pixel)(p->poses[o.view].x.data(), Y.data(), r);
        rho(r[0] * r[0] + r[1] * r[1], f);
        c += o.weight * f[0];
      }
      return c;
    };
    double cost = cost_at(X);
    for (int it = 0; it < max_iterations; ++it) {
      Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
      Eigen::Vector3d g = Eigen::Vector3d::Zero();
      Jet3 Xj[3];
      for (int k = 0; k < 3; ++k) Xj[k] = Jet3(X(k), k);
      for (size_t i = begin; i < end; ++i) {
        const LocalObservation& o = p->observations[i];
        for (int k = 0; k < 6; ++k) pose[k] = Jet3(p->poses[o.view].x(k));
        Jet3 r[2];
        ReprojectionError(&p->CameraOf(o.view), p->poses[o.view].R0, o.pixel)(pose.data(), Xj, r);
        Eigen::Matrix<double, 2, 3> J;
        J << r[0].v.transpose(), r[1].v.transpose();
        const Eigen::Vector2d e(r[0].a, r[1].a);
        double f[3];
        rho(e.squaredNorm(), f);
        H += o.weight * f[1] * J.transpose() * J;
        g += o.weight * f[1] * J.transpose() * e;
      }
      const Eigen::Vector3d dx = H.ldlt().solve(-g);
      if (!dx.allFinite()) break;
      const Eigen::Vector3d Y = X + dx;
      const double c = cost_at(Y);
      if (!(c < cost)) break;
      X = Y;
      cost = c;
    }
    begin = end;
  }
}

}  // namespace

LocalHessianStatus BuildLocalBundleProblem(const Reconstruction& tracks, const LocalMotion& motion,
                                           const LocalHessianOptions& options, LocalBundleProblem* problem,
                                           const ObservationShares* shares, const FreeIntrinsics* free) {
  *problem = LocalBundleProblem();
  problem->loss = options.loss;
  problem->max_reprojection_px =
      options.loss.type == LossType::kCauchy ? options.cauchy_max_reprojection_px : options.max_reprojection_px;
  const int n = motion.num_views();
  if (n < 2 || static_cast<int>(motion.local_poses.size()) != n) return LocalHessianStatus::kInvalidInput;
  std::vector<const Image*> images(n);
  problem->poses.resize(n);
  problem->cameras.resize(n);
  problem->view_intrinsics.assign(n, -1);
  LocalIntrinsics& in = problem->intrinsics;
  for (int k = 0; k < n; ++k) {
    const auto it = tracks.images.find(motion.image_ids[k]);
    if (it == tracks.images.end()) return LocalHessianStatus::kInvalidInput;
    images[k] = &it->second;
    const auto cam = tracks.cameras.find(it->second.camera_id);
    if (cam == tracks.cameras.end()) return LocalHessianStatus::kInvalidInput;
    problem->cameras[k] = &cam->second;
    if (free && free->count(cam->first)) in.camera_ids.push_back(cam->first);
    const Pose& pose = motion.local_poses[k];
    if (!pose.q().coeffs().allFinite() || !pose.t().allFinite()) return LocalHessianStatus::kInvalidInput;
    problem->poses[k] = PoseBlock::FromPose(pose);
  }
  std::sort(in.camera_ids.begin(), in.camera_ids.end());
  in.camera_ids.erase(std::unique(in.camera_ids.begin(), in.camera_ids.end()), in.camera_ids.end());
  for (const uint32_t id : in.camera_ids) {
    in.cameras.push_back(tracks.cameras.at(id));
    in.free.push_back(free->at(id));
    in.directions.push_back(IntrinsicDirections(in.cameras.back(), in.free.back()));
    in.offset.push_back(in.num_unknowns);
    in.num_unknowns += static_cast<int>(in.free.back().size());
  }
  for (int k = 0; k < n; ++k) {  // views of free cameras project through the copies
    const uint32_t id = images[k]->camera_id;
    const auto c = std::lower_bound(in.camera_ids.begin(), in.camera_ids.end(), id);
    if (c == in.camera_ids.end() || *c != id) continue;
    problem->view_intrinsics[k] = static_cast<int>(c - in.camera_ids.begin());
  }
  // View of each image in the motion, as (image id, view) sorted by id; an image twice is
  // invalid. A sorted vector and buffers reused across tracks: this loop runs over every
  // track element of every motion in each local Hessian pass (with a std::map and per-track
  // vectors it would be a fifth of the problem's construction, triangulation included).
  std::vector<std::pair<uint32_t, int>> view_of_image(n);
  for (int k = 0; k < n; ++k) view_of_image[k] = {motion.image_ids[k], k};
  std::sort(view_of_image.begin(), view_of_image.end());
  for (int k = 1; k < n; ++k)
    if (view_of_image[k].first == view_of_image[k - 1].first) return LocalHessianStatus::kInvalidInput;

  TriangulationOptions tri;
  tri.huber_px = options.loss.scale;
  tri.outlier_px = options.max_reprojection_px;
  tri.min_angle_deg = options.min_triangulation_angle_deg;
  // Observation of the current track in each view, if any (the first one if an image sees
  // the track twice).
  std::vector<int> point2D_idx(n);
  std::vector<TrackView> views;
  std::vector<int> view_of;
  views.reserve(n);
  view_of.reserve(n);
  const bool warm = motion.track_points.size() == motion.track_ids.size();
  for (size_t ti = 0; ti < motion.track_ids.size(); ++ti) {
    const uint64_t track_id = motion.track_ids[ti];
    const auto pit = tracks.points3D.find(track_id);
    if (pit == tracks.points3D.end()) return LocalHessianStatus::kInvalidInput;
    std::fill(point2D_idx.begin(), point2D_idx.end(), -1);
    for (const TrackElement& el : pit->second.track) {
      const auto v = std::lower_bound(view_of_image.begin(), view_of_image.end(), std::make_pair(el.image_id, 0));
      if (v == view_of_image.end() || v->first != el.image_id || point2D_idx[v->second] >= 0) continue;
      if (el.point2D_idx >= images[v->second]->points2D.size()) return LocalHessianStatus::kInvalidInput;
      point2D_idx[v->second] = static_cast<int>(el.point2D_idx);
    }
    views.clear();
    view_of.clear();
    for (int k = 0; k < n; ++k) {
      if (point2D_idx[k] < 0) continue;
      views.push_back({motion.local_poses[k], problem->cameras[k], images[k]->points2D[point2D_idx[k]].xy});
      view_of.push_back(k);
    }
    if (views.size() < 2) continue;
    problem->num_candidate_observations += static_cast<int>(views.size());
    const TriangulatedPoint X =
        warm ? TriangulateTrackFrom(views, motion.track_points[ti], tri) : TriangulateTrack(views, tri);
    if (!X.ok) continue;
    // Keep the observations consistent with the point; a point needs two of them.
    const size_t first = problem->observations.size();
    for (size_t v = 0; v < views.size(); ++v)
      if (X.residuals_px[v] <= problem->max_reprojection_px) {
        double w = 1.0;
        if (shares) {
          const auto it = shares->find({motion.image_ids[view_of[v]], track_id});
          if (it != shares->end() && it->second > 0) w = 1.0 / it->second;
        }
        problem->observations.push_back({view_of[v], static_cast<int>(problem->points.size()), views[v].pixel, w});
      }
    if (problem->observations.size() - first < 2) {
      problem->observations.resize(first);
      continue;
    }
    problem->points.push_back(X.X);
    problem->point_track.push_back(static_cast<int>(ti));
  }
  const int m = static_cast<int>(problem->points.size());
  if (m < std::max(options.min_points, 1)) return LocalHessianStatus::kTooFewPoints;
  if (options.loss.type != LossType::kHuber) MovePointsToLossMinimum(problem, kLossMinimumIterations);
  problem->observation_weight = AttenuationWeight(m, options.attenuation_q);
  problem->prior_center.resize(6 * n);
  for (int k = 0; k < n; ++k) problem->prior_center.segment<6>(6 * k) = problem->poses[k].x;
  return LocalHessianStatus::kOk;
}

bool SolveLocalBundle(const SolverOptions& solver, LocalBundleProblem* p, bool fix_gauge) {
  if (solver.max_iterations > 0) {
    // The robust loss on the pixel error, then the attenuation weight on the squared residual:
    // one loss object per distinct weight (1, or 1/n with shared_observation_weighting), shared
    // by the observations that have it.
    std::map<double, std::unique_ptr<ceres::LossFunction>> losses;
    ceres::Problem::Options po;
    po.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    ceres::Problem problem(po);
    for (auto& pose : p->poses) problem.AddParameterBlock(pose.x.data(), 6);
    for (auto& X : p->points) problem.AddParameterBlock(X.data(), 3);
    LocalIntrinsics& in = p->intrinsics;
    for (size_t c = 0; c < in.cameras.size(); ++c) {
      std::vector<double>& params = in.cameras[c].params;
      problem.AddParameterBlock(params.data(), static_cast<int>(params.size()),
                                IntrinsicsManifold(in.cameras[c], in.free[c]));
    }
    for (const LocalObservation& o : p->observations) {
      std::unique_ptr<ceres::LossFunction>& l = losses[o.weight];
      if (!l)
        l = std::make_unique<ceres::ScaledLoss>(p->loss.CreateLossFunction(), p->observation_weight * o.weight,
                                                ceres::TAKE_OWNERSHIP);
      const int c = p->view_intrinsics[o.view];
      if (c >= 0) {
        problem.AddResidualBlock(
            CreateReprojectionErrorWithIntrinsics(in.cameras[c].model, p->poses[o.view].R0, o.pixel), l.get(),
            p->poses[o.view].x.data(), p->points[o.point].data(), in.cameras[c].params.data());
      } else {
        problem.AddResidualBlock(ReprojectionError::Create(p->cameras[o.view], p->poses[o.view].R0, o.pixel),
                                 l.get(), p->poses[o.view].x.data(), p->points[o.point].data());
      }
    }
    if (p->prior.size() > 0 && !p->prior.isZero(0.0)) {
      const Eigen::MatrixXd A = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(p->prior).operatorSqrt();
      std::vector<double*> blocks;
      for (auto& pose : p->poses) blocks.push_back(pose.x.data());
      problem.AddResidualBlock(new PosePriorCost(A, p->prior_center), nullptr, blocks);
    }
    if (fix_gauge && p->poses.size() >= 2) HoldPoseAndScale(&p->poses[0], &p->poses[1], &problem);
    ceres::Solver::Options so = CeresSolverOptions(solver);
    auto ordering = std::make_shared<ceres::ParameterBlockOrdering>();
    for (auto& X : p->points) ordering->AddElementToGroup(X.data(), 0);
    for (auto& pose : p->poses) ordering->AddElementToGroup(pose.x.data(), 1);
    for (Camera& camera : in.cameras) ordering->AddElementToGroup(camera.params.data(), 1);
    so.linear_solver_ordering = ordering;
    ceres::Solver::Summary summary;
    ceres::Solve(so, &problem, &summary);
    if (summary.termination_type == ceres::FAILURE || !std::isfinite(summary.final_cost)) return false;
  }
  // h is taken in the chart r = r0 Exp(omega) centred at the solution.
  for (auto& pose : p->poses) pose.Relinearize();
  return true;
}

double MedianDepth(const LocalBundleProblem& p) {
  std::vector<double> depth;
  depth.reserve(p.observations.size());
  for (const LocalObservation& o : p.observations) {
    const PoseBlock& b = p.poses[o.view];
    const Eigen::Matrix3d R = b.R0 * ExpSO3(b.x.tail<3>());
    depth.push_back((R * (p.points[o.point] - b.x.head<3>())).z());
  }
  if (depth.empty()) return 1.0;
  std::nth_element(depth.begin(), depth.begin() + depth.size() / 2, depth.end());
  return depth[depth.size() / 2];
}

double RobustCost(const LocalBundleProblem& p) {
  const std::unique_ptr<ceres::LossFunction> loss(p.loss.CreateLossFunction());
  const auto rho = [&loss](double s) {
    if (!loss) return s;
    double r[3];
    loss->Evaluate(s, r);
    return r[0];
  };
  const double cap = p.max_reprojection_px * p.max_reprojection_px;
  double cost = 0.0;
  for (const LocalObservation& o : p.observations) {
    const ReprojectionError e(&p.CameraOf(o.view), p.poses[o.view].R0, o.pixel);
    double r[2];
    e(p.poses[o.view].x.data(), p.points[o.point].data(), r);
    cost += rho(std::min(r[0] * r[0] + r[1] * r[1], cap));
  }
  const int dropped = std::max(0, p.num_candidate_observations - static_cast<int>(p.observations.size()));
  return cost + dropped * rho(cap);
}

double RmsReprojectionPx(const LocalBundleProblem& p) {
  double sum = 0.0;
  for (const LocalObservation& o : p.observations) {
    const ReprojectionError e(&p.CameraOf(o.view), p.poses[o.view].R0, o.pixel);
    double r[2];
    e(p.poses[o.view].x.data(), p.points[o.point].data(), r);
    sum += r[0] * r[0] + r[1] * r[1];
  }
  return p.observations.empty() ? 0.0 : std::sqrt(sum / p.observations.size());
}

std::string LocalHessianOptions::Check() const {
  if (const std::string m = CheckRanges(*this, "local_hessian"); !m.empty()) return m;
  return "";
}

}  // namespace pgba
