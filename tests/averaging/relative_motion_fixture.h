// Test fixture of the averaging tests: ground-truth camera layouts and relative motions
// (pairs, triplets) derived from them with seeded noise. Independent of the front end: the
// truth is the layout, the inputs are built from it exactly as the pair/triplet stages
// define them (x_2 = R_21 x_1 + t_21 with unit t_21; triplet local poses = a random
// global->local similarity applied to the true poses, then perturbed).
#pragma once

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <random>
#include <vector>

#include "pgba/geometry/pose.h"
#include "pgba/geometry/rotation.h"
#include "pgba/geometry/sim3.h"
#include "pgba/scene/reconstruction.h"
#include "pgba/scene/view_graph.h"

namespace pgba::test {

enum class Layout {
  kOrbit,   // ring around an object, cameras looking at its centre
  kAerial,  // parallel strips looking down: centres nearly collinear within a strip
  kVideo,   // a camera moving along a nearly straight path in a plane, looking sideways
};

inline const char* LayoutName(Layout l) {
  return l == Layout::kOrbit ? "orbit" : l == Layout::kAerial ? "aerial" : "video";
}

// World->camera rotation of a camera at C looking at `target` with `up` roughly up.
inline Eigen::Matrix3d LookAt(const Eigen::Vector3d& C, const Eigen::Vector3d& target, const Eigen::Vector3d& up) {
  const Eigen::Vector3d z = (target - C).normalized();
  const Eigen::Vector3d x = up.cross(z).normalized();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Matrix3d R;
  R.row(0) = x.transpose();
  R.row(1) = y.transpose();
  R.row(2) = z.transpose();
  return R;
}

struct GroundTruth {
  std::map<uint32_t, Pose> poses;
  double extent = 1.0;      // diagonal of the centres' bounding box
  double pair_radius = 1.0;  // cameras closer than this see common points
};

inline GroundTruth MakeLayout(Layout layout, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> n01(0.0, 1.0);
  GroundTruth gt;
  uint32_t id = 1;
  auto jitter = [&](double deg) { return ExpSO3(n01(rng) * deg * M_PI / 180.0 * Eigen::Vector3d(n01(rng), n01(rng), n01(rng)).normalized()); };
  if (layout == Layout::kOrbit) {
    const int n = 36;
    for (int i = 0; i < n; ++i) {
      const double a = 2 * M_PI * i / n;
      const Eigen::Vector3d C(10 * std::cos(a), 10 * std::sin(a), 2.0 + 0.5 * n01(rng));
      gt.poses[id++] = Pose::FromRC(jitter(2.0) * LookAt(C, Eigen::Vector3d(0, 0, 0.3 * n01(rng)), Eigen::Vector3d::UnitZ()), C);
    }
    gt.pair_radius = 7.0;  // about 4 neighbours on each side
  } else if (layout == Layout::kAerial) {
    const int strips = 3, per_strip = 14;
    for (int s = 0; s < strips; ++s)
      for (int i = 0; i < per_strip; ++i) {
        const Eigen::Vector3d C(1.0 * i + 0.05 * n01(rng), 3.0 * s + 0.05 * n01(rng), 10.0 + 0.05 * n01(rng));
        // Looking down; alternate strips flown in opposite directions.
        Eigen::Matrix3d R;
        R << 1, 0, 0, 0, -1, 0, 0, 0, -1;
        if (s % 2) R = R * Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ()).toRotationMatrix();
        gt.poses[id++] = Pose::FromRC(jitter(2.0) * R, C);
      }
    gt.pair_radius = 4.5;  // overlap along the strip and with the neighbouring strips
  } else {
    const int n = 40;
    for (int i = 0; i < n; ++i) {
      const double x = 0.5 * i;
      const Eigen::Vector3d C(x, 0.3 * std::sin(0.15 * x) + 0.02 * n01(rng), 1.6 + 0.02 * n01(rng));
      gt.poses[id++] =
          Pose::FromRC(jitter(3.0) * LookAt(C, C + Eigen::Vector3d(0.2 * n01(rng), 5.0, 0.0), Eigen::Vector3d::UnitZ()), C);
    }
    gt.pair_radius = 2.6;  // about 5 neighbours on each side
  }
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
  for (const auto& [i, p] : gt.poses) {
    lo = lo.cwiseMin(p.C());
    hi = hi.cwiseMax(p.C());
  }
  gt.extent = (hi - lo).norm();
  return gt;
}

struct NoiseModel {
  double rotation_deg = 0.3;   // RMS angle of the noise rotation of a relative rotation
  double direction_deg = 0.3;  // RMS angle of the noise rotation of a pair direction
  double centre_rel = 0.003;   // triplet local centre noise, fraction of the triplet size
};

// A random rotation of RMS angle `deg` (isotropic: per-axis standard deviation deg / sqrt(3)).
template <typename Rng>
Eigen::Matrix3d NoiseRotation(Rng& rng, double deg) {
  std::normal_distribution<double> n(0.0, deg / std::sqrt(3.0) * M_PI / 180.0);
  return ExpSO3(Eigen::Vector3d(n(rng), n(rng), n(rng)));
}


// The pair (id1, id2) of the true poses: R_21 and the unit t_21 with noise.
template <typename Rng>
TwoViewGeometry MakePair(const std::map<uint32_t, Pose>& poses, uint32_t id1, uint32_t id2, const NoiseModel& noise,
                         Rng& rng) {
  const Pose& P1 = poses.at(id1);
  const Pose& P2 = poses.at(id2);
  TwoViewGeometry p;
  p.image_id1 = id1;
  p.image_id2 = id2;
  p.R_21 = NoiseRotation(rng, noise.rotation_deg) * P2.R() * P1.R().transpose();
  p.t_21 = NoiseRotation(rng, noise.direction_deg) * (P2.R() * (P1.C() - P2.C())).normalized();
  return p;
}

// The triplet `ids` in a random local frame (global->local similarity *truth, scale
// 0.2..5), its local rotations and centres perturbed.
template <typename Rng>
LocalMotion MakeTriplet(const std::map<uint32_t, Pose>& poses, const std::array<uint32_t, 3>& ids,
                    const NoiseModel& noise, Rng& rng, Sim3* truth) {
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  LocalMotion t;
  t.image_ids.assign(ids.begin(), ids.end());
  t.local_poses.resize(3);
  Sim3& d = *truth;
  d.s = std::exp(std::log(0.2) + (std::log(5.0) - std::log(0.2)) * u01(rng));
  d.R = RandomRotation(rng);
  d.t = Eigen::Vector3d(u01(rng), u01(rng), u01(rng)) * 10.0 - Eigen::Vector3d::Constant(5.0);
  double size = 0.0;
  for (int k = 0; k < 3; ++k) size = std::max(size, (poses.at(ids[k]).C() - poses.at(ids[(k + 1) % 3]).C()).norm());
  std::normal_distribution<double> centre_noise(0.0, noise.centre_rel * size * d.s);
  for (int k = 0; k < 3; ++k) {
    const Pose local = d.Apply(poses.at(ids[k]));
    const Eigen::Vector3d dc(centre_noise(rng), centre_noise(rng), centre_noise(rng));
    // Two local rotations differ by sqrt(2) x this noise: the same as a pair's.
    t.local_poses[k] =
        Pose::FromRC(NoiseRotation(rng, noise.rotation_deg / std::sqrt(2.0)) * local.R(), local.C() + dc);
  }
  return t;
}

struct RelativeMotions {
  std::vector<TwoViewGeometry> pairs;
  std::vector<LocalMotion> triplets;
  std::vector<Sim3> true_global_to_local;  // per triplet, before noise
};

// Pairs between cameras closer than the layout's pair radius; triplets = all triangles of
// that graph.
inline RelativeMotions MakeRelativeMotions(const GroundTruth& gt, const NoiseModel& noise, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  RelativeMotions m;
  std::vector<uint32_t> ids;
  for (const auto& [id, p] : gt.poses) ids.push_back(id);
  auto close = [&](uint32_t a, uint32_t b) { return (gt.poses.at(a).C() - gt.poses.at(b).C()).norm() < gt.pair_radius; };
  for (size_t a = 0; a < ids.size(); ++a)
    for (size_t b = a + 1; b < ids.size(); ++b) {
      if (!close(ids[a], ids[b])) continue;
      TwoViewGeometry p = MakePair(gt.poses, ids[a], ids[b], noise, rng);
      p.num_inliers = 100 + static_cast<int>(200 * u01(rng));
      p.num_tracks = p.num_inliers + 20;
      m.pairs.push_back(p);
      for (size_t c = b + 1; c < ids.size(); ++c) {
        if (!close(ids[a], ids[c]) || !close(ids[b], ids[c])) continue;
        Sim3 d;
        LocalMotion t = MakeTriplet(gt.poses, {ids[a], ids[b], ids[c]}, noise, rng, &d);
        const int tracks = 50 + static_cast<int>(100 * u01(rng));
        for (int k = 0; k < tracks; ++k) t.track_ids.push_back(k);
        m.triplets.push_back(t);
        m.true_global_to_local.push_back(d);
      }
    }
  return m;
}

// Pairs of images sharing at least `min_pair_tracks` tracks of `scene` and triplets whose
// three images share at least `min_triplet_tracks` tracks (and whose three pairs exist),
// with relative motions from the scene's true poses and the given noise: the view graph of
// a real scene, the motions of a perfect front end plus noise.
inline RelativeMotions MakeRelativeMotionsFromTracks(const Reconstruction& scene, const NoiseModel& noise,
                                                     uint64_t seed, int min_pair_tracks = 20,
                                                     int min_triplet_tracks = 30) {
  std::map<uint32_t, Pose> poses;
  for (const auto& [id, im] : scene.images) poses[id] = im.pose;
  std::map<std::pair<uint32_t, uint32_t>, int> pair_count;
  std::map<std::array<uint32_t, 3>, std::vector<uint64_t>> triplet_tracks;
  for (const auto& [pid, point] : scene.points3D) {
    std::vector<uint32_t> ids;
    for (const TrackElement& e : point.track) ids.push_back(e.image_id);
    std::sort(ids.begin(), ids.end());
    ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
    for (size_t a = 0; a < ids.size(); ++a)
      for (size_t b = a + 1; b < ids.size(); ++b) {
        ++pair_count[{ids[a], ids[b]}];
        for (size_t c = b + 1; c < ids.size(); ++c) triplet_tracks[{ids[a], ids[b], ids[c]}].push_back(pid);
      }
  }
  std::mt19937_64 rng(seed);
  RelativeMotions m;
  for (const auto& [key, count] : pair_count) {
    if (count < min_pair_tracks) continue;
    TwoViewGeometry p = MakePair(poses, key.first, key.second, noise, rng);
    p.num_tracks = p.num_inliers = count;
    m.pairs.push_back(p);
  }
  auto has_pair = [&](uint32_t a, uint32_t b) {
    auto it = pair_count.find({a, b});
    return it != pair_count.end() && it->second >= min_pair_tracks;
  };
  for (const auto& [ids, tracks] : triplet_tracks) {
    if (static_cast<int>(tracks.size()) < min_triplet_tracks || !has_pair(ids[0], ids[1]) ||
        !has_pair(ids[0], ids[2]) || !has_pair(ids[1], ids[2]))
      continue;
    Sim3 d;
    LocalMotion t = MakeTriplet(poses, ids, noise, rng, &d);
    t.track_ids = tracks;
    m.triplets.push_back(t);
    m.true_global_to_local.push_back(d);
  }
  return m;
}

// A Reconstruction holding just the images (names "img_<id>.jpg") of the layout.
inline Reconstruction MakeTracks(const GroundTruth& gt) {
  Reconstruction rec;
  Camera cam;
  rec.cameras[1] = cam;
  for (const auto& [id, p] : gt.poses) {
    Image im;
    im.image_id = id;
    im.name = "img_" + std::to_string(id) + ".jpg";
    im.camera_id = 1;
    rec.images[id] = im;
  }
  return rec;
}

struct PoseErrors {
  std::vector<double> rotation_deg;
  std::vector<double> centre_rel;  // after Sim(3) alignment, fraction of the extent
};

inline double Median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}
inline double Max(const std::vector<double>& v) { return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end()); }

// Rotation errors after the best global rotation (chordal mean of R_est^T R_gt); rotation
// averaging fixes one rotation, the truth another.
inline std::vector<double> RotationErrorsDeg(const std::map<uint32_t, Eigen::Matrix3d>& est,
                                             const std::map<uint32_t, Pose>& gt) {
  Eigen::Matrix3d sum = Eigen::Matrix3d::Zero();
  for (const auto& [id, R] : est) sum += R.transpose() * gt.at(id).R();
  const Eigen::Matrix3d A = ClosestRotation(sum);  // R_gt ~ R_est A
  std::vector<double> err;
  for (const auto& [id, R] : est) err.push_back(RotationAngleDeg(R * A, gt.at(id).R()));
  return err;
}

// Centre errors after Sim(3) alignment (Umeyama) of the estimate to the truth. Collinear
// centres leave Umeyama's rotation undetermined: then, if the estimated rotations are given,
// the alignment rotation comes from them (X_gt = s A X_est + t with R_est = R_gt A) and the
// scale and translation from the centres.
inline std::vector<double> CentreErrorsRel(const std::map<uint32_t, Eigen::Vector3d>& est,
                                           const std::map<uint32_t, Pose>& gt, double extent,
                                           const std::map<uint32_t, Eigen::Matrix3d>* est_rotations = nullptr) {
  std::vector<Eigen::Vector3d> src, dst;
  for (const auto& [id, C] : est) {
    src.push_back(C);
    dst.push_back(gt.at(id).C());
  }
  Sim3 align;
  if (!EstimateSim3(src, dst, &align)) {
    if (!est_rotations) return std::vector<double>(est.size(), 1e9);
    Eigen::Matrix3d sum = Eigen::Matrix3d::Zero();
    for (const auto& [id, C] : est) sum += gt.at(id).R().transpose() * est_rotations->at(id);
    align.R = ClosestRotation(sum);
    Eigen::Vector3d ms = Eigen::Vector3d::Zero(), md = Eigen::Vector3d::Zero();
    for (size_t k = 0; k < src.size(); ++k) {
      ms += src[k] / src.size();
      md += dst[k] / src.size();
    }
    double num = 0.0, den = 0.0;
    for (size_t k = 0; k < src.size(); ++k) {
      num += (dst[k] - md).dot(align.R * (src[k] - ms));
      den += (src[k] - ms).squaredNorm();
    }
    align.s = num / den;
    align.t = md - align.s * align.R * ms;
  }
  std::vector<double> err;
  for (size_t k = 0; k < src.size(); ++k) err.push_back((align.Apply(src[k]) - dst[k]).norm() / extent);
  return err;
}

}  // namespace pgba::test
