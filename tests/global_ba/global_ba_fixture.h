// Test helpers of the global BA tests (header only): perturbed initial poses, ground-truth
// pose errors after similarity alignment, the sigma metric of ARCHITECTURE.md, a
// point-based BA reference (poses + points, Huber, SPARSE_SCHUR), and triplets with local
// Hessians built like the pipeline builds them (triplet BA, then one local BA iteration).
#pragma once

#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <vector>

#include "modules/local_hessian/local_hessian.h"
#include "pgba/geometry/rotation.h"
#include "pgba/geometry/sim3.h"
#include "pgba/geometry/triangulation.h"
#include "pgba/optim/ceres_solver_options.h"
#include "pgba/optim/pose_parameterization.h"
#include "tests/local_hessian/ring_scene.h"

namespace pgba::testing {

// Rotation by exactly `deg` about a random axis, centre moved by exactly `shift`.
inline std::map<uint32_t, Pose> PerturbPoses(const std::map<uint32_t, Pose>& poses, double deg, double shift,
                                             uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> n(0.0, 1.0);
  std::map<uint32_t, Pose> out;
  for (const auto& [id, p] : poses) {
    const Eigen::Vector3d d = Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized();
    out[id] = Pose::FromRC(p.R() * RandomRotationOfAngle(rng, deg * M_PI / 180.0), p.C() + shift * d);
  }
  return out;
}

inline double SceneExtent(const std::map<uint32_t, Pose>& poses) {
  double e = 0.0;
  for (const auto& [a, pa] : poses)
    for (const auto& [b, pb] : poses) e = std::max(e, (pa.C() - pb.C()).norm());
  return e;
}

struct PoseErrors {
  double rot_deg_median = 0.0;
  double rot_deg_max = 0.0;
  double center_rel_median = 0.0;
};

// Errors of `est` against `gt` after the Sim(3) aligning the centres.
inline PoseErrors GroundTruthErrors(const std::map<uint32_t, Pose>& est, const std::map<uint32_t, Pose>& gt) {
  std::vector<Eigen::Vector3d> src, dst;
  for (const auto& [id, p] : est) {
    src.push_back(p.C());
    dst.push_back(gt.at(id).C());
  }
  Sim3 S;
  if (!EstimateSim3(src, dst, &S)) return {1e9, 1e9, 1e9};
  std::vector<double> rot, cen;
  const double extent = SceneExtent(gt);
  for (const auto& [id, p] : est) {
    const Pose a = S.Apply(p);
    rot.push_back(RotationAngleDeg(a.R(), gt.at(id).R()));
    cen.push_back((a.C() - gt.at(id).C()).norm() / extent);
  }
  auto median = [](std::vector<double> v) {
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    return v[v.size() / 2];
  };
  return {median(rot), *std::max_element(rot.begin(), rot.end()), median(cen)};
}

// The sigma metric: every track triangulated with the poses held fixed (linear + robust
// Gauss-Newton), RMS of the observations' reprojection errors under 4 px.
inline double SigmaPx(const Reconstruction& rec, const std::map<uint32_t, Pose>& poses) {
  double sum = 0.0;
  size_t n = 0;
  for (const auto& [pid, pt] : rec.points3D) {
    std::vector<TrackView> views;
    for (const TrackElement& el : pt.track) {
      const auto it = poses.find(el.image_id);
      if (it == poses.end()) continue;
      const Image& im = rec.images.at(el.image_id);
      views.push_back({it->second, &rec.cameras.at(im.camera_id), im.points2D[el.point2D_idx].xy});
    }
    if (views.size() < 2) continue;
    const TriangulatedPoint X = TriangulateTrack(views);
    if (!X.ok) continue;
    for (double r : X.residuals_px)
      if (r < 4.0) {
        sum += r * r;
        ++n;
      }
  }
  return n ? std::sqrt(sum / n) : 1e9;
}

// Classical BA over poses and triangulated points from `initial` (Huber 1 px, SPARSE_SCHUR,
// gauge: first pose fixed and one centre coordinate of the second).
inline std::map<uint32_t, Pose> PointBasedBA(const Reconstruction& rec, const std::map<uint32_t, Pose>& initial,
                                             int* iterations = nullptr) {
  std::map<uint32_t, PoseBlock> blocks;
  for (const auto& [id, p] : initial) blocks[id] = PoseBlock::FromPose(p);
  std::vector<Eigen::Vector3d> points;
  points.reserve(rec.points3D.size());
  struct Obs {
    uint32_t image;
    size_t point;
    Eigen::Vector2d xy;
  };
  std::vector<Obs> obs;
  for (const auto& [pid, pt] : rec.points3D) {
    std::vector<TrackView> views;
    std::vector<const TrackElement*> els;
    for (const TrackElement& el : pt.track) {
      if (!initial.count(el.image_id)) continue;
      const Image& im = rec.images.at(el.image_id);
      views.push_back({initial.at(el.image_id), &rec.cameras.at(im.camera_id), im.points2D[el.point2D_idx].xy});
      els.push_back(&el);
    }
    if (views.size() < 2) continue;
    const TriangulatedPoint X = TriangulateTrack(views);
    if (!X.ok) continue;
    points.push_back(X.X);
    for (size_t v = 0; v < views.size(); ++v) obs.push_back({els[v]->image_id, points.size() - 1, views[v].pixel});
  }
  ceres::Problem problem;
  auto ordering = std::make_shared<ceres::ParameterBlockOrdering>();
  for (auto& X : points) {
    problem.AddParameterBlock(X.data(), 3);
    ordering->AddElementToGroup(X.data(), 0);
  }
  for (auto& [id, b] : blocks) {
    problem.AddParameterBlock(b.x.data(), 6);
    ordering->AddElementToGroup(b.x.data(), 1);
  }
  for (const Obs& o : obs) {
    PoseBlock& b = blocks.at(o.image);
    problem.AddResidualBlock(ReprojectionError::Create(&rec.cameras.at(rec.images.at(o.image).camera_id), b.R0, o.xy),
                             new ceres::HuberLoss(1.0), b.x.data(), points[o.point].data());
  }
  auto first = blocks.begin();
  auto second = std::next(first);
  problem.SetParameterBlockConstant(first->second.x.data());
  int coord = 0;
  (second->second.x.head<3>() - first->second.x.head<3>()).cwiseAbs().maxCoeff(&coord);
  problem.SetManifold(second->second.x.data(), new ceres::SubsetManifold(6, {coord}));
  SolverOptions solver;
  solver.linear_solver_type = ceres::SPARSE_SCHUR;
  solver.max_iterations = 100;
  solver.function_tolerance = 1e-10;
  solver.num_threads = 2;
  ceres::Solver::Options so = CeresSolverOptions(solver);
  so.linear_solver_ordering = ordering;
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
  if (iterations) *iterations = static_cast<int>(summary.iterations.size()) - 1;
  std::map<uint32_t, Pose> out;
  for (const auto& [id, b] : blocks) out[id] = b.ToPose();
  return out;
}

// Triplets as the pipeline hands them over: local poses = truth mapped by a random
// similarity and refined by a converged triplet BA on the noisy observations; then the
// local Hessians (one local BA iteration, default options).
struct TripletsWithHessians {
  std::vector<LocalMotion> triplets;
  LocalHessianResult hessians;
};
inline TripletsWithHessians BuildTripletsWithHessians(const Reconstruction& rec, int window, bool closed,
                                                      uint64_t seed, const LocalHessianOptions& options = PaperTripletLocalHessianOptions()) {
  std::mt19937_64 rng(seed);
  TripletsWithHessians out;
  out.triplets = MakeRingTriplets(rec, window, closed, rng);
  LocalHessianOptions triplet_ba = options;
  triplet_ba.solver.max_iterations = 20;
  const LocalHessianResult refined = ComputeLocalHessians(rec, out.triplets, triplet_ba);
  for (size_t i = 0; i < out.triplets.size(); ++i)
    if (refined.hessians[i].status == LocalHessianStatus::kOk)
      std::copy(refined.hessians[i].local_poses.begin(), refined.hessians[i].local_poses.end(),
                out.triplets[i].local_poses.begin());
  out.hessians = ComputeLocalHessians(rec, out.triplets, options);
  return out;
}

}  // namespace pgba::testing
