#include "modules/triplets/triplet_estimation.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "pgba/io/option_ranges.h"
#include "modules/triplets/intrinsics_uncertainty.h"
#include "pgba/geometry/rotation.h"
#include "pgba/geometry/sim3.h"
#include "pgba/geometry/triangulation.h"
#include "pgba/optim/bundle_adjuster.h"
#include "pgba/util/logging.h"
#include "pgba/util/upper_median.h"

namespace pgba {
namespace {

// Index in `pairs` of the pair of triplet positions u != v.
int PairIndex(int u, int v) {
  const int a = std::min(u, v), b = std::max(u, v);
  return a == 0 ? b - 1 : 2;
}

TrackView ViewOf(const TrackIndex& index, uint32_t image_id, int64_t point2D_idx, const Pose& pose) {
  TrackView v;
  v.pose = pose;
  v.camera = &index.CameraOf(image_id);
  v.pixel = index.Pixel(image_id, static_cast<uint32_t>(point2D_idx));
  return v;
}

// The triplet's working model: its three images (with their observations) and the
// triangulated tracks, ids as in the input so that track_ids come out directly.
Reconstruction MakeLocalModel(const TrackIndex& index, const std::array<uint32_t, 3>& ids,
                              const std::array<Pose, 3>& poses) {
  Reconstruction rec;
  for (int k = 0; k < 3; ++k) {
    Image image = index.tracks().images.at(ids[k]);
    image.pose = poses[k];
    rec.cameras.emplace(image.camera_id, index.CameraOf(ids[k]));
    rec.images.emplace(ids[k], std::move(image));
  }
  return rec;
}

// Length of the baseline hinge -> c of an open triplet, in the base pair's scale: each track
// seen by all three views is triangulated again from (hinge, c) with a unit baseline, and
// the ratio of its distances to the hinge centre (base pair / unit) is one measurement of
// the length; the median is robust to a minority of bad tracks. Empty without a finite,
// positive median.
std::optional<double> BaselineScale(const TrackIndex& index, const std::array<uint32_t, 3>& ids, int hinge, int c,
                                    const Pose& hinge_pose, const Pose& hinge_to_c,
                                    const std::vector<const TripletTrack*>& tracks,
                                    const std::vector<Eigen::Vector3d>& base_points, const TriangulationOptions& tri) {
  const Pose unit_c = Pose::FromQt(hinge_to_c.q() * hinge_pose.q(), hinge_to_c.q() * hinge_pose.t() + hinge_to_c.t());
  const Eigen::Vector3d centre = hinge_pose.C();
  std::vector<double> ratios;
  for (size_t k = 0; k < tracks.size(); ++k) {
    const TripletTrack& t = *tracks[k];
    const TriangulatedPoint X = TriangulateTrack({ViewOf(index, ids[hinge], t.point2D_idx[hinge], hinge_pose),
                                                  ViewOf(index, ids[c], t.point2D_idx[c], unit_c)},
                                                 tri);
    if (!X.ok || std::max(X.residuals_px[0], X.residuals_px[1]) > tri.outlier_px) continue;
    const double d = (X.X - centre).norm();
    if (d > 0.0) ratios.push_back((base_points[k] - centre).norm() / d);
  }
  if (ratios.empty()) return std::nullopt;
  const double s = UpperMedian(ratios);
  if (!std::isfinite(s) || !(s > 0.0)) return std::nullopt;
  return s;
}

}  // namespace

Pose RelativePoseOfPair(const TwoViewGeometry& pair, uint32_t from, uint32_t to) {
  if (from == pair.image_id1 && to == pair.image_id2) return Pose::FromQt(Eigen::Quaterniond(pair.R_21), pair.t_21);
  const Eigen::Matrix3d R = pair.R_21.transpose();
  return Pose::FromQt(Eigen::Quaterniond(R), -(R * pair.t_21));
}

double TripletScore(int num_tracks_all_views, double median_angle_deg, const TripletOptions& options) {
  return num_tracks_all_views * std::min(1.0, median_angle_deg / options.score_angle_deg);
}

TripletEstimate EstimateTriplet(const TrackIndex& index, const std::array<uint32_t, 3>& ids,
                                const std::array<const TwoViewGeometry*, 3>& pairs, const TripletOptions& options,
                                uint64_t seed) {
  TripletEstimate out;
  auto reject = [&out](TripletRejection r) {
    out.rejection = r;
    return out;
  };
  const std::vector<TripletTrack> tracks = TracksOfTriplet(index, ids);
  if (static_cast<int>(tracks.size()) < options.min_tracks) return reject(TripletRejection::kTooFewTracks);

  // 1. Base pair (positions va, vb) and third view vc. An open triplet (one pair missing)
  // takes its base among the two pairs it has, so the third view hangs on the hinge.
  static constexpr int kPairViews[3][2] = {{0, 1}, {0, 2}, {1, 2}};
  int best = -1, missing = -1;
  double best_score = -1.0, best_angle = 0.0;
  for (int p = 0; p < 3; ++p) {
    if (!pairs[p]) {
      missing = p;
      continue;
    }
    const double s = TripletScore(pairs[p]->num_inliers, pairs[p]->median_triangulation_angle_deg, options);
    best_angle = std::max(best_angle, pairs[p]->median_triangulation_angle_deg);
    if (s > best_score) best_score = s, best = p;
  }
  if (best < 0) return reject(TripletRejection::kInitFailed);
  if (best_angle < options.min_triangulation_angle_deg) return reject(TripletRejection::kDegenerate);
  const int va = kPairViews[best][0], vb = kPairViews[best][1], vc = 3 - va - vb;
  std::array<Pose, 3> poses;
  poses[vb] = RelativePoseOfPair(*pairs[best], ids[va], ids[vb]);

  // 2. Scale from the base pair's points; third view placed on them.
  TriangulationOptions tri;
  tri.outlier_px = options.outlier_threshold_px;
  tri.min_angle_deg = options.min_track_angle_deg;
  std::vector<const TripletTrack*> seen_by_all;
  std::vector<Eigen::Vector3d> bearings_c, points;
  for (const TripletTrack& t : tracks) {
    if (t.NumViews() < 3) continue;
    const TriangulatedPoint X = TriangulateTrack(
        {ViewOf(index, ids[va], t.point2D_idx[va], poses[va]), ViewOf(index, ids[vb], t.point2D_idx[vb], poses[vb])},
        tri);
    if (!X.ok || std::max(X.residuals_px[0], X.residuals_px[1]) > options.outlier_threshold_px) continue;
    seen_by_all.push_back(&t);
    bearings_c.push_back(index.Bearing(ids[vc], static_cast<uint32_t>(t.point2D_idx[vc])));
    points.push_back(X.X);
  }
  if (missing >= 0) {
    // Open: the hinge's pair to vc gives its rotation and direction; only the length of
    // that baseline is unknown, measured on the tracks seen by all three views.
    const int hinge = PairIndex(va, vc) == missing ? vb : va;
    if (static_cast<int>(points.size()) < options.open_min_tracks_all_views)
      return reject(TripletRejection::kTooFewTracks);
    const Pose hc = RelativePoseOfPair(*pairs[PairIndex(hinge, vc)], ids[hinge], ids[vc]);
    const std::optional<double> s = BaselineScale(index, ids, hinge, vc, poses[hinge], hc, seen_by_all, points, tri);
    if (!s) return reject(TripletRejection::kInitFailed);
    poses[vc] = Pose::FromQt(hc.q() * poses[hinge].q(), hc.q() * poses[hinge].t() + *s * hc.t());
  } else {
    // Closed: OpenGV absolute pose (P3P in RANSAC); its rotation must close with the pairs.
    if (static_cast<int>(points.size()) < options.absolute_pose.min_inliers)
      return reject(TripletRejection::kTooFewTracks);
    AbsolutePoseOptions ap = options.absolute_pose;
    ap.seed = seed;
    const AbsolutePoseResult abs = EstimateAbsolutePose(bearings_c, points, index.CameraOf(ids[vc]).MeanFocal(), ap);
    if (!abs.success) return reject(TripletRejection::kInitFailed);
    poses[vc] = abs.pose;
    for (int v : {va, vb}) {
      const Eigen::Matrix3d R_cv = poses[vc].R() * poses[v].R().transpose();
      const Eigen::Matrix3d R_pair = RelativePoseOfPair(*pairs[PairIndex(v, vc)], ids[v], ids[vc]).R();
      if (RotationAngleDeg(R_cv, R_pair) > options.max_rotation_cycle_deg)
        return reject(TripletRejection::kRotationCycle);
    }
  }

  // 3. Every track seen by >= 2 views, robustly triangulated with the three poses.
  Reconstruction local = MakeLocalModel(index, ids, poses);
  for (const TripletTrack& t : tracks) {
    std::vector<TrackView> views;
    std::vector<int> which;
    for (int v = 0; v < 3; ++v) {
      if (t.point2D_idx[v] < 0) continue;
      views.push_back(ViewOf(index, ids[v], t.point2D_idx[v], poses[v]));
      which.push_back(v);
    }
    const TriangulatedPoint X = TriangulateTrack(views, tri);
    if (!X.ok) continue;
    Point3D point;
    point.point3D_id = t.track_id;
    point.xyz = X.X;
    for (size_t k = 0; k < views.size(); ++k)
      if (X.residuals_px[k] <= options.outlier_threshold_px)
        point.track.push_back({ids[which[k]], static_cast<uint32_t>(t.point2D_idx[which[k]])});
    if (point.track.size() >= 2) local.points3D.emplace(t.track_id, std::move(point));
  }
  if (static_cast<int>(local.points3D.size()) < options.min_tracks) return reject(TripletRejection::kTooFewTracks);

  // 4. Triplet BA, outlier observations removed and re-solved. Self-calibration frees the
  // cameras' intrinsics only where the triplet determines them (TripletOptions::
  // intrinsics_max_sd_px, measured at the initial solution); a freed BA that does not converge
  // is replaced by the one with the intrinsics held.
  BundleAdjustmentProblem problem;
  problem.image_ids = {ids[0], ids[1], ids[2]};
  problem.fix_gauge = true;
  problem.gauge_anchor = ids[va];
  problem.gauge_scale = ids[vb];
  if (options.refine_intrinsics) {
    // The principal point stays held whatever the switches: three views do not determine it.
    IntrinsicsOptions switches;
    switches.refine_principal_point_without_calibration = false;
    const FreeIntrinsics free = SelectFreeIntrinsics(local.cameras, switches);
    const IntrinsicsUncertainty u = EstimateIntrinsicsUncertainty(local, problem.image_ids, free, ids[va], ids[vb]);
    out.intrinsics_max_sd_px = u.max_stddev_px;
    for (const auto& [camera_id, indices] : free) {
      const auto sd = u.camera_max_stddev_px.find(camera_id);
      const bool determined = u.ok && sd != u.camera_max_stddev_px.end() && sd->second <= options.intrinsics_max_sd_px;
      if (determined || !local.cameras.at(camera_id).has_prior_focal_length) problem.free_intrinsics[camera_id] = indices;
    }
  }
  BundleAdjusterOptions ba = options.bundle_adjuster;
  ba.solver.num_threads = 1;
  const Reconstruction initial = problem.free_intrinsics.empty() ? Reconstruction() : local;
  BundleAdjustmentSummary summary;
  for (int round = 0;; ++round) {
    summary = BundleAdjust(problem, ba, &local);
    out.ba_iterations += summary.iterations;
    if (!problem.free_intrinsics.empty() && !(summary.usable && summary.converged)) {
      PGBA_LOG_DEBUG << "triplet " << ids[0] << " " << ids[1] << " " << ids[2]
                     << ": BA with free intrinsics did not converge, held instead";
      problem.free_intrinsics.clear();
      local = initial;
      round = -1;
      continue;
    }
    // A round that used up its iteration budget will not converge in the next one either
    // (weak geometry: the cost crawls along a flat valley); re-solving after outlier removal
    // would only spend up to three more budgets on a triplet that is rejected in the end.
    if (!summary.usable || !summary.converged) return reject(TripletRejection::kNotConverged);
    if (round == 3 || FilterObservations(options.outlier_threshold_px, &local) == 0) break;
    if (static_cast<int>(local.points3D.size()) < options.min_tracks) return reject(TripletRejection::kTooFewTracks);
  }
  out.intrinsics_freed = !problem.free_intrinsics.empty();
  PGBA_LOG_DEBUG << "triplet " << ids[0] << " " << ids[1] << " " << ids[2] << ": BA " << out.ba_iterations
                 << " iterations, " << local.points3D.size() << " points, intrinsics "
                 << (out.intrinsics_freed ? "freed" : "held") << " (sd " << out.intrinsics_max_sd_px
                 << " px at the corner), focal " << local.cameras.begin()->second.MeanFocal() << ", "
                 << summary.message;
  if (!summary.converged) return reject(TripletRejection::kNotConverged);

  // 5. Checks on the refined triplet.
  if (static_cast<int>(local.points3D.size()) < options.min_tracks) return reject(TripletRejection::kTooFewTracks);
  std::vector<double> angles;
  double sq = 0.0;
  int num_obs = 0;
  for (const auto& [pid, point] : local.points3D) {
    std::vector<TrackView> views;
    for (const TrackElement& el : point.track)
      views.push_back(ViewOf(index, el.image_id, el.point2D_idx, local.images.at(el.image_id).pose));
    angles.push_back(MaxTriangulationAngleDeg(views, point.xyz));
    for (double e : ObservationErrorsPx(local, pid)) sq += e * e, ++num_obs;
    out.num_tracks_all_views += point.track.size() == 3;
  }
  out.median_triangulation_angle_deg = UpperMedian(angles);
  const double rms = std::sqrt(sq / std::max(1, num_obs));
  if (out.median_triangulation_angle_deg < options.min_triangulation_angle_deg)
    return reject(TripletRejection::kDegenerate);
  if (!(rms <= options.max_rms_px)) return reject(TripletRejection::kHighRms);

  // 6. Canonical gauge: view 0 at the identity, |c_1 - c_0| = 1.
  const Pose P0 = local.images.at(ids[0]).pose;
  const Eigen::Vector3d C0 = P0.C();
  const double d01 = (local.images.at(ids[1]).pose.C() - C0).norm();
  const double d02 = (local.images.at(ids[2]).pose.C() - C0).norm();
  if (!(d01 > 1e-6 * std::max(1.0, d02))) return reject(TripletRejection::kDegenerate);
  Sim3 to_canonical;
  to_canonical.s = 1.0 / d01;
  to_canonical.R = P0.R();
  to_canonical.t = -to_canonical.s * (to_canonical.R * C0);
  LocalMotion& triplet = out.triplet;
  triplet.image_ids.assign(ids.begin(), ids.end());
  triplet.local_poses.resize(3);
  for (int k = 0; k < 3; ++k) triplet.local_poses[k] = to_canonical.Apply(local.images.at(ids[k]).pose);
  triplet.local_poses[0] = Pose();  // exactly, not up to rounding
  for (const auto& [pid, point] : local.points3D) triplet.track_ids.push_back(pid);
  triplet.rms_px = rms;
  out.score = TripletScore(out.num_tracks_all_views, out.median_triangulation_angle_deg, options);
  return out;
}

std::string TripletOptions::Check() const {
  if (const std::string m = CheckRanges(*this, "triplets"); !m.empty()) return m;
  return "";
}

const char* TripletRejectionName(TripletRejection r) {
  switch (r) {
    case TripletRejection::kNone: return "none";
    case TripletRejection::kRotationCycle: return "rotation_cycle";
    case TripletRejection::kTooFewTracks: return "too_few_tracks";
    case TripletRejection::kInitFailed: return "init_failed";
    case TripletRejection::kNotConverged: return "not_converged";
    case TripletRejection::kHighRms: return "high_rms";
    case TripletRejection::kDegenerate: return "degenerate";
  }
  return "unknown";
}

}  // namespace pgba
