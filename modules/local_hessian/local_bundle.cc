#include "modules/local_hessian/local_bundle.h"

#include <ceres/ceres.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <memory>

#include "pgba/geometry/triangulation.h"

namespace pgba {

double AttenuationWeight(int num_points, double q) {
  if (!(q > 0) || std::isinf(q) || num_points <= 0) return 1.0;
  const double m = num_points;
  const double gamma = m * q / (m + q);
  return gamma / m;
}

namespace {

// Observation of a track in the triplet's view k, if any (first one if an image sees the
// track twice).
struct TrackInTriplet {
  std::array<int, 3> point2D_idx{-1, -1, -1};
};

// Pose prior of the local BA: A (x - x_in) over the three pose blocks, A^T A = prior.
struct PosePriorCost {
  PosePriorCost(const Matrix18d& sqrt_prior, const Vector18d& center) : A(sqrt_prior), center(center) {}
  template <typename T>
  bool operator()(const T* p0, const T* p1, const T* p2, T* r) const {
    const T* poses[3] = {p0, p1, p2};
    T d[18];
    for (int k = 0; k < 3; ++k)
      for (int i = 0; i < 6; ++i) d[6 * k + i] = poses[k][i] - T(center(6 * k + i));
    for (int i = 0; i < 18; ++i) {
      r[i] = A(i, 0) * d[0];
      for (int j = 1; j < 18; ++j) r[i] += A(i, j) * d[j];
    }
    return true;
  }
  Matrix18d A;
  Vector18d center;
};

}  // namespace

LocalHessianStatus BuildLocalBundleProblem(const Reconstruction& tracks, const Triplet& triplet,
                                           const LocalHessianOptions& options, LocalBundleProblem* problem,
                                           const ObservationShares* shares) {
  *problem = LocalBundleProblem();
  problem->huber_px = options.huber_px;
  std::array<const Image*, 3> images{};
  for (int k = 0; k < 3; ++k) {
    const auto it = tracks.images.find(triplet.image_ids[k]);
    if (it == tracks.images.end()) return LocalHessianStatus::kInvalidInput;
    images[k] = &it->second;
    const auto cam = tracks.cameras.find(it->second.camera_id);
    if (cam == tracks.cameras.end()) return LocalHessianStatus::kInvalidInput;
    problem->cameras[k] = &cam->second;
    const Pose& pose = triplet.local_poses[k];
    if (!pose.q().coeffs().allFinite() || !pose.t().allFinite()) return LocalHessianStatus::kInvalidInput;
    problem->poses[k] = PoseBlock::FromPose(pose);
  }
  if (triplet.image_ids[0] == triplet.image_ids[1] || triplet.image_ids[0] == triplet.image_ids[2] ||
      triplet.image_ids[1] == triplet.image_ids[2])
    return LocalHessianStatus::kInvalidInput;

  TriangulationOptions tri;
  tri.huber_px = options.huber_px;
  tri.outlier_px = options.max_reprojection_px;
  tri.min_angle_deg = options.min_triangulation_angle_deg;
  for (const uint64_t track_id : triplet.track_ids) {
    const auto pit = tracks.points3D.find(track_id);
    if (pit == tracks.points3D.end()) return LocalHessianStatus::kInvalidInput;
    TrackInTriplet t;
    for (const TrackElement& el : pit->second.track) {
      for (int k = 0; k < 3; ++k) {
        if (el.image_id != triplet.image_ids[k] || t.point2D_idx[k] >= 0) continue;
        if (el.point2D_idx >= images[k]->points2D.size()) return LocalHessianStatus::kInvalidInput;
        t.point2D_idx[k] = static_cast<int>(el.point2D_idx);
      }
    }
    std::vector<TrackView> views;
    std::vector<int> view_of;
    for (int k = 0; k < 3; ++k) {
      if (t.point2D_idx[k] < 0) continue;
      views.push_back({triplet.local_poses[k], problem->cameras[k], images[k]->points2D[t.point2D_idx[k]].xy});
      view_of.push_back(k);
    }
    if (views.size() < 2) continue;
    const TriangulatedPoint X = TriangulateTrack(views, tri);
    if (!X.ok) continue;
    // Keep the observations consistent with the point; a point needs two of them.
    std::vector<LocalObservation> kept;
    for (size_t v = 0; v < views.size(); ++v)
      if (X.residuals_px[v] <= options.max_reprojection_px) {
        double w = 1.0;
        if (shares) {
          const auto it = shares->find({triplet.image_ids[view_of[v]], track_id});
          if (it != shares->end() && it->second > 0) w = 1.0 / it->second;
        }
        kept.push_back({view_of[v], static_cast<int>(problem->points.size()), views[v].pixel, w});
      }
    if (kept.size() < 2) continue;
    problem->points.push_back(X.X);
    problem->observations.insert(problem->observations.end(), kept.begin(), kept.end());
  }
  const int m = static_cast<int>(problem->points.size());
  if (m < std::max(options.min_points, 1)) return LocalHessianStatus::kTooFewPoints;
  problem->observation_weight = AttenuationWeight(m, options.attenuation_q);
  for (int k = 0; k < 3; ++k) problem->prior_center.segment<6>(6 * k) = problem->poses[k].x;
  return LocalHessianStatus::kOk;
}

bool SolveLocalBundle(int max_iterations, LocalBundleProblem* p) {
  if (max_iterations > 0) {
    // Huber on the pixel error, then the attenuation weight on the squared residual; one
    // loss object shared by all observations of weight 1, one of its own for the others
    // (shared_observation_weighting).
    ceres::ScaledLoss loss(new ceres::HuberLoss(p->huber_px), p->observation_weight, ceres::TAKE_OWNERSHIP);
    std::vector<std::unique_ptr<ceres::LossFunction>> own;
    ceres::Problem::Options po;
    po.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    ceres::Problem problem(po);
    for (auto& pose : p->poses) problem.AddParameterBlock(pose.x.data(), 6);
    for (auto& X : p->points) problem.AddParameterBlock(X.data(), 3);
    for (const LocalObservation& o : p->observations) {
      ceres::LossFunction* l = &loss;
      if (o.weight != 1.0) {
        own.emplace_back(new ceres::ScaledLoss(new ceres::HuberLoss(p->huber_px), p->observation_weight * o.weight,
                                               ceres::TAKE_OWNERSHIP));
        l = own.back().get();
      }
      problem.AddResidualBlock(ReprojectionError::Create(p->cameras[o.view], p->poses[o.view].R0, o.pixel), l,
                               p->poses[o.view].x.data(), p->points[o.point].data());
    }
    if (!p->prior.isZero(0.0)) {
      const Matrix18d A = Eigen::SelfAdjointEigenSolver<Matrix18d>(p->prior).operatorSqrt();
      problem.AddResidualBlock(
          new ceres::AutoDiffCostFunction<PosePriorCost, 18, 6, 6, 6>(new PosePriorCost(A, p->prior_center)), nullptr,
          p->poses[0].x.data(), p->poses[1].x.data(), p->poses[2].x.data());
    }
    ceres::Solver::Options so;
    so.linear_solver_type = ceres::DENSE_SCHUR;
    auto ordering = std::make_shared<ceres::ParameterBlockOrdering>();
    for (auto& X : p->points) ordering->AddElementToGroup(X.data(), 0);
    for (auto& pose : p->poses) ordering->AddElementToGroup(pose.x.data(), 1);
    so.linear_solver_ordering = ordering;
    so.max_num_iterations = max_iterations;
    so.num_threads = 1;
    so.logging_type = ceres::SILENT;
    so.minimizer_progress_to_stdout = false;
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

double RmsReprojectionPx(const LocalBundleProblem& p) {
  double sum = 0.0;
  for (const LocalObservation& o : p.observations) {
    const ReprojectionError e(p.cameras[o.view], p.poses[o.view].R0, o.pixel);
    double r[2];
    e(p.poses[o.view].x.data(), p.points[o.point].data(), r);
    sum += r[0] * r[0] + r[1] * r[1];
  }
  return p.observations.empty() ? 0.0 : std::sqrt(sum / p.observations.size());
}

}  // namespace pgba
