#include "averaging/track_positioning.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "pgba/io/option_ranges.h"
#include "pgba/optim/ceres_solver_options.h"
#include "pgba/scene/camera.h"
#include "pgba/scene/triangulate_model.h"
#include "pgba/util/error.h"
#include "pgba/util/id_ordered_map.h"
#include "pgba/util/logging.h"
#include "pgba/util/timer.h"
#include "pgba/util/upper_median.h"

namespace pgba {
namespace {

// Reprojection error of point X in a view of fixed rotation R and free centre C.
struct FixedRotationReprojection {
  template <typename T>
  bool operator()(const T* C, const T* X, T* r) const {
    const T d[3] = {X[0] - C[0], X[1] - C[1], X[2] - C[2]};
    T x_cam[3];
    for (int a = 0; a < 3; ++a) x_cam[a] = T(R(a, 0)) * d[0] + T(R(a, 1)) * d[1] + T(R(a, 2)) * d[2];
    T pixel[2];
    ProjectToPixel(model, params, x_cam, pixel);
    r[0] = pixel[0] - T(observed.x());
    r[1] = pixel[1] - T(observed.y());
    return true;
  }
  Eigen::Matrix3d R;
  Eigen::Vector2d observed;
  CameraModel model;
  const double* params;
};

// Sum of the distances of three centres to their centroid.
double Spread(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d g = (a + b + c) / 3.0;
  return (a - g).norm() + (b - g).norm() + (c - g).norm();
}

}  // namespace

void ValidateTrackPositioningOptions(const TrackPositioningOptions& o) {
  if (const std::string m = o.Check(); !m.empty()) throw InputError("track positioning options: " + m);
}

bool PositionOnTracks(const Reconstruction& tracks, const std::vector<LocalMotion>& triplets,
                      const TrackPositioningOptions& options, std::map<uint32_t, Pose>* poses,
                      TrackPositioningSummary* summary_out) {
  ValidateTrackPositioningOptions(options);
  Timer timer;
  TrackPositioningSummary summary;
  auto finish = [&](bool ok, const std::string& message) {
    summary.message = message;
    summary.seconds = timer.Seconds();
    if (summary_out) *summary_out = summary;
    return ok;
  };
  if (!options.enabled) return finish(false, "disabled");
  if (poses->size() < 2) return finish(false, "fewer than two posed images");

  TriangulationOptions triangulation;
  triangulation.min_angle_deg = options.min_track_angle_deg;
  Reconstruction model = TriangulateModel(tracks, *poses, triangulation);

  // One parameter block per centre and per point, each held in one array in id order: Ceres
  // orders an elimination group by address (util/id_ordered_map.h), and std::map nodes lie
  // where the allocator put them (another thread count, another --out: other last bits).
  IdOrderedMap<Eigen::Vector3d> C;
  for (const auto& [id, pose] : *poses) C[id] = pose.C();
  std::vector<Eigen::Vector3d> X;
  X.reserve(model.points3D.size());  // no reallocation once addresses are handed to Ceres
  std::map<uint32_t, int> observations_per_image;
  ceres::Problem::Options problem_options;
  problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  const std::unique_ptr<ceres::LossFunction> loss(options.loss.CreateLossFunction());
  std::vector<ceres::ResidualBlockId> blocks;
  for (const auto& [pid, point] : model.points3D) {
    int seen = 0;
    for (const TrackElement& e : point.track) seen += poses->count(e.image_id) > 0;
    if (seen < 2) continue;
    ++summary.num_points;
    Eigen::Vector3d& xyz = X.emplace_back(point.xyz);
    for (const TrackElement& e : point.track) {
      auto pose = poses->find(e.image_id);
      if (pose == poses->end()) continue;
      const Image& image = tracks.images.at(e.image_id);
      const Camera& camera = tracks.CameraOf(image);
      auto* cost = new ceres::AutoDiffCostFunction<FixedRotationReprojection, 2, 3, 3>(new FixedRotationReprojection{
          pose->second.R(), image.points2D.at(e.point2D_idx).xy, camera.model, camera.params.data()});
      blocks.push_back(problem.AddResidualBlock(cost, loss.get(), C.at(e.image_id).data(), xyz.data()));
      ++observations_per_image[e.image_id];
    }
  }
  summary.num_observations = static_cast<int>(blocks.size());
  if (observations_per_image.size() < 2) return finish(false, "no track seen by two posed images");

  // Gauge: the best observed image's centre, and the scale through one coordinate of the
  // centre farthest from it.
  const uint32_t anchor =
      std::max_element(observations_per_image.begin(), observations_per_image.end(), [](const auto& a, const auto& b) {
        return a.second < b.second;
      })->first;
  uint32_t far = anchor;
  for (const auto& [id, n] : observations_per_image)
    if ((C.at(id) - C.at(anchor)).norm() > (C.at(far) - C.at(anchor)).norm()) far = id;
  if (far == anchor || !((C.at(far) - C.at(anchor)).norm() > 0.0)) return finish(false, "coincident centres");
  problem.SetParameterBlockConstant(C.at(anchor).data());
  int axis = 0;
  (C.at(far) - C.at(anchor)).cwiseAbs().maxCoeff(&axis);
  problem.SetManifold(C.at(far).data(), new ceres::SubsetManifold(3, {axis}));

  auto inlier_rms = [&]() {
    double sum = 0.0;
    int n = 0;
    for (ceres::ResidualBlockId b : blocks) {
      double r[2];
      problem.EvaluateResidualBlock(b, /*apply_loss_function=*/false, nullptr, r, nullptr);
      const double e2 = r[0] * r[0] + r[1] * r[1];
      if (e2 < 16.0) {
        sum += e2;
        ++n;
      }
    }
    return n ? std::sqrt(sum / n) : 0.0;
  };
  summary.initial_rms_px = inlier_rms();

  ceres::Solver::Options solver = CeresSolverOptions(options.solver);
  auto ordering = std::make_shared<ceres::ParameterBlockOrdering>();
  for (Eigen::Vector3d& xyz : X)
    if (problem.HasParameterBlock(xyz.data())) ordering->AddElementToGroup(xyz.data(), 0);
  for (auto& [id, c] : C)
    if (problem.HasParameterBlock(c.data())) ordering->AddElementToGroup(c.data(), 1);
  solver.linear_solver_ordering = ordering;
  ceres::Solver::Summary result;
  ceres::Solve(solver, &problem, &result);
  summary.iterations = static_cast<int>(result.iterations.size());
  if (!result.IsSolutionUsable()) return finish(false, "solve failed: " + result.message);
  summary.final_rms_px = inlier_rms();
  for (const auto& [id, c] : C)
    if (!c.allFinite()) return finish(false, "the refined centres are not finite");

  // Centroid 0 and median lambda_t = 1, as translation averaging leaves them.
  std::vector<double> lambdas;
  for (const LocalMotion& t : triplets) {
    if (!C.count(t.image_ids[0]) || !C.count(t.image_ids[1]) || !C.count(t.image_ids[2])) continue;
    const double global = Spread(C.at(t.image_ids[0]), C.at(t.image_ids[1]), C.at(t.image_ids[2]));
    const double local = Spread(t.local_poses[0].C(), t.local_poses[1].C(), t.local_poses[2].C());
    if (global > 0.0 && std::isfinite(local / global)) lambdas.push_back(local / global);
  }
  const double f = lambdas.empty() ? 1.0 : UpperMedian(lambdas);
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const auto& [id, c] : C) centroid += c;
  centroid /= static_cast<double>(C.size());
  for (auto& [id, pose] : *poses) pose = Pose::FromRC(pose.R(), f * (C.at(id) - centroid));
  summary.ran = true;
  PGBA_LOG_DEBUG << "track positioning: " << summary.num_points << " points, " << summary.num_observations
                << " observations, " << summary.iterations << " iterations, reprojection RMS (< 4 px) "
                << summary.initial_rms_px << " -> " << summary.final_rms_px << " px";
  return finish(true, "ok");
}

std::string TrackPositioningOptions::Check() const {
  if (const std::string m = CheckRanges(*this, "global_init.track_positioning"); !m.empty()) return m;
  return "";
}

}  // namespace pgba
