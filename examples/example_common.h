// What examples 2 and 3 share: controlled initial poses, the gauge-free error measure, the
// point-based BA, the paper's triplets on a ring, and pgba's default pointless BA over
// whole-track motions. Each function is the few library calls a pipeline stage makes.
#pragma once

#include <algorithm>
#include <map>
#include <random>
#include <vector>

#include "evaluation/ground_truth.h"
#include "global_ba/global_ba.h"
#include "local_hessian/whole_track_motions.h"
#include "mapper/pose_refinement.h"
#include "pgba/geometry/rotation.h"
#include "pgba/optim/bundle_adjuster.h"
#include "pgba/scene/triangulate_model.h"

namespace pgba::examples {

using Poses = std::map<uint32_t, Pose>;

// Each rotation turned by exactly `deg` about a random axis, each centre moved by exactly
// `shift` (the pipeline gets its start from rotation and translation averaging; a controlled
// start isolates the final adjustment).
inline Poses Perturbed(const Poses& poses, double deg, double shift, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> n01;
  Poses out;
  for (const auto& [id, p] : poses) {
    const Eigen::Vector3d dir = Eigen::Vector3d(n01(rng), n01(rng), n01(rng)).normalized();
    out[id] = Pose::FromRC(p.R() * RandomRotationOfAngle(rng, deg * M_PI / 180), p.C() + shift * dir);
  }
  return out;
}

// Median relative rotation error (deg) of `est` against `ref` over all image pairs:
// angle(R_j R_i^T, R*_j R*_i^T). Gauge-free: no alignment, so nothing to hide errors in.
inline double RelRotErrDeg(const Poses& est, const Poses& ref) {
  std::vector<Pose> a, b;
  for (const auto& [id, p] : est) {
    a.push_back(p);
    b.push_back(ref.at(id));
  }
  GroundTruthErrors e;
  RelativePoseErrors(a, b, &e);
  return e.rel_rot_err_deg_median;
}

// Classical BA: points triangulated from `initial`, then poses and points together (Huber
// 1 px, Schur complement on the points), gauge: one pose and one distance held.
inline Poses PointBasedBA(const Reconstruction& tracks, const Poses& initial, size_t* num_points = nullptr) {
  Reconstruction model = TriangulateModel(tracks, initial);
  BundleAdjustmentProblem problem;
  ChooseGauge(model, &problem);
  BundleAdjust(problem, BundleAdjusterOptions{}, &model);
  if (num_points) *num_points = model.points3D.size();
  Poses out;
  for (const auto& [id, im] : model.images) out[id] = im.pose;
  return out;
}

// The paper's relative motions on a ring of n views (ids 1..n): triplets (i, i+1, i+2) and
// (i, i+1, i+3), each with the tracks that >= 2 of its views see. Their local poses start
// from `start` (in the pipeline: each triplet's own 5-point estimate; any frame would do,
// the similarity d_s absorbs it), and the local BA of TripletHessians converges them.
// `closed` false: no triplet wraps from the last views to the first.
inline std::vector<LocalMotion> RingTriplets(const Reconstruction& tracks, const Poses& start, bool closed) {
  const uint32_t n = static_cast<uint32_t>(start.size());
  std::vector<LocalMotion> triplets;
  for (uint32_t i = 0; i < n; ++i)
    for (uint32_t b : {2u, 3u}) {
      if (!closed && i + b >= n) continue;
      LocalMotion m;
      m.image_ids = {i + 1, (i + 1) % n + 1, (i + b) % n + 1};
      for (uint32_t id : m.image_ids) m.local_poses.push_back(start.at(id));
      for (const auto& [pid, pt] : tracks.points3D) {
        int seen = 0;
        for (const TrackElement& el : pt.track)
          seen += std::count(m.image_ids.begin(), m.image_ids.end(), el.image_id) > 0;
        if (seen >= 2) m.track_ids.push_back(pid);
      }
      triplets.push_back(m);
    }
  return triplets;
}

// The local BAs of the triplets with the paper's settings (attenuation Q = 10, Huber 1 px),
// run to convergence: x0_s is each triplet's own optimum and h_s is taken there.
inline LocalHessianResult TripletHessians(const Reconstruction& tracks, const std::vector<LocalMotion>& triplets) {
  LocalHessianOptions options = PaperTripletLocalHessianOptions();
  options.solver.max_iterations = 20;
  return ComputeLocalHessians(tracks, triplets, options);
}

// pgba's default pointless BA: whole-track motions (every track whole in one motion), h_s
// taken at the initial poses with every observation at weight 1 (no attenuation, no local
// BA: the motion's frame is the global one, no rank test: a direction one motion does not
// see, another does), the global BA without a robust loss on the motions (the observations
// were robustified inside h_s), then every h_s re-taken at each solution and the step kept
// only if the true reprojection cost falls, until that cost has converged: Gauss-Newton on
// the point-based cost with the points eliminated. These are the options structs' defaults.
// `num_params`: its unknowns (6 per pose + 7 per motion).
inline Poses WholeTrackPointlessBA(const Reconstruction& tracks, const Poses& initial, int* num_params = nullptr) {
  const std::vector<LocalMotion> motions = SelectWholeTrackMotions(tracks, initial, WholeTrackMotionOptions{});
  const LocalHessianOptions lh;
  const LocalHessianResult hessians = ComputeLocalHessians(tracks, motions, lh);
  const GlobalBAResult r = RelinearizedGlobalBA(tracks, lh, initial, motions, hessians.hessians, GlobalBAOptions{});
  if (num_params) *num_params = r.summary.num_params;
  return r.poses;
}

}  // namespace pgba::examples
