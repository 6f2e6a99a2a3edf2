// Small self-made test fixture (header only) for the local Hessian and global BA tests:
// cameras on a ring looking at a bumpy sphere of points, noisy pixel observations, and
// triplets whose local frames are the ground truth mapped by random similarities.
// (The project's synthetic scenes live in modules/synthetic; this fixture keeps these
// numerical tests small, fast and independent of it.)
#pragma once

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <vector>

#include "pgba/geometry/rotation.h"
#include "pgba/geometry/sim3.h"
#include "pgba/scene/reconstruction.h"
#include "pgba/scene/view_graph.h"

namespace pgba::testing {

struct RingSceneOptions {
  int num_images = 24;
  int num_points = 2000;
  double ring_radius = 8.0;
  double object_radius = 2.5;
  // Points are visible from cameras within this angle of their outward normal.
  double visibility_deg = 60.0;
  // Fraction of the full circle covered by the cameras (1 = closed ring).
  double arc_fraction = 1.0;
  double noise_px = 0.5;
  double outlier_fraction = 0.0;
  // Focal length (pixels, 1280 x 960 images): 800 is a wide lens; tens of thousands with a
  // ring radius far beyond the object radius make a telephoto ring (near-orthographic views).
  double focal_px = 800.0;
  // Radial distortion: 0 gives a PINHOLE camera, otherwise SIMPLE_RADIAL with this k.
  double k1 = 0.0;
  // Standard deviation of the aim point around the centre (scene units).
  double target_jitter = 0.3;
  uint64_t seed = 7;
};

inline Pose LookAt(const Eigen::Vector3d& C, const Eigen::Vector3d& target) {
  const Eigen::Vector3d forward = (target - C).normalized();
  const Eigen::Vector3d right = forward.cross(Eigen::Vector3d::UnitZ()).normalized();
  const Eigen::Vector3d down = forward.cross(right);
  Eigen::Matrix3d R;
  R.row(0) = right.transpose();
  R.row(1) = down.transpose();
  R.row(2) = forward.transpose();
  return Pose::FromRC(R, C);
}

// `rec` holds the true poses and points and the noisy observations.
inline Reconstruction MakeRingScene(const RingSceneOptions& o) {
  std::mt19937_64 rng(o.seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  Reconstruction rec;
  Camera cam;
  cam.camera_id = 1;
  cam.model = o.k1 == 0.0 ? CameraModel::kPinhole : CameraModel::kSimpleRadial;
  cam.width = 1280;
  cam.height = 960;
  cam.params = o.k1 == 0.0 ? std::vector<double>{o.focal_px, o.focal_px, 640.0, 480.0}
                           : std::vector<double>{o.focal_px, 640.0, 480.0, o.k1};
  rec.cameras[1] = cam;
  for (int i = 0; i < o.num_images; ++i) {
    const double a = 2.0 * M_PI * o.arc_fraction * i / o.num_images;
    const Eigen::Vector3d C(o.ring_radius * std::cos(a), o.ring_radius * std::sin(a), 0.8 * std::sin(3.0 * a));
    const Eigen::Vector3d target =
        o.target_jitter * Eigen::Vector3d(normal(rng), normal(rng), normal(rng));
    Image im;
    im.image_id = static_cast<uint32_t>(i + 1);
    im.name = "img" + std::to_string(i + 1) + ".jpg";
    im.camera_id = 1;
    im.pose = LookAt(C, target);
    rec.images[im.image_id] = im;
  }
  for (int p = 0; p < o.num_points; ++p) {
    Eigen::Vector3d n(normal(rng), normal(rng), 0.5 * normal(rng));
    n.normalize();
    const Eigen::Vector3d X = (o.object_radius * (0.8 + 0.4 * uni(rng))) * n;
    std::vector<TrackElement> track;
    for (auto& [id, im] : rec.images) {
      const Eigen::Vector3d to_cam = (im.pose.C() - X).normalized();
      if (to_cam.dot(n) < std::cos(o.visibility_deg * M_PI / 180.0)) continue;
      const Eigen::Vector3d xc = im.pose.ToCamera(X);
      if (xc.z() <= 0) continue;
      Eigen::Vector2d px = cam.Project(xc);
      if (px.x() < 0 || px.y() < 0 || px.x() >= cam.width || px.y() >= cam.height) continue;
      px += o.noise_px * Eigen::Vector2d(normal(rng), normal(rng));
      if (uni(rng) < o.outlier_fraction) px = Eigen::Vector2d(uni(rng) * cam.width, uni(rng) * cam.height);
      im.points2D.push_back({px, kNoPoint3D});
      track.push_back({id, static_cast<uint32_t>(im.points2D.size() - 1)});
    }
    if (track.size() < 2) {
      for (const TrackElement& el : track) rec.images[el.image_id].points2D.pop_back();
      continue;
    }
    rec.AddPoint3D(X, track);
  }
  return rec;
}

inline std::map<uint32_t, Pose> PosesOf(const Reconstruction& rec) {
  std::map<uint32_t, Pose> poses;
  for (const auto& [id, im] : rec.images) poses[id] = im.pose;
  return poses;
}

// A random similarity (scale in [0.3, 3], any rotation, translation ~ 5).
template <typename Rng>
Sim3 RandomSim3(Rng& rng) {
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  Sim3 s;
  s.s = std::exp(1.2 * uni(rng));
  s.R = RandomRotation(rng);
  s.t = 5.0 * Eigen::Vector3d(uni(rng), uni(rng), uni(rng));
  return s;
}

// Triplet (a, b, c) with local poses = true poses mapped by a random global->local
// similarity, and the tracks seen by all three images.
template <typename Rng>
LocalMotion MakeTriplet(const Reconstruction& rec, std::array<uint32_t, 3> ids, Rng& rng) {
  LocalMotion t;
  t.image_ids.assign(ids.begin(), ids.end());
  t.local_poses.resize(3);
  t.global_to_local = RandomSim3(rng);
  for (int k = 0; k < 3; ++k) t.local_poses[k] = t.global_to_local.Apply(rec.images.at(ids[k]).pose);
  for (const auto& [pid, pt] : rec.points3D) {
    int seen = 0;
    for (const TrackElement& el : pt.track) seen += el.image_id == ids[0] || el.image_id == ids[1] || el.image_id == ids[2];
    if (seen == 3) t.track_ids.push_back(pid);
  }
  return t;
}

// Triplets of images within `window` consecutive ring positions (wrapping around a closed
// ring): (i, i+a, i+b) for 0 < a < b < window.
template <typename Rng>
std::vector<LocalMotion> MakeRingTriplets(const Reconstruction& rec, int window, bool closed, Rng& rng) {
  const int n = static_cast<int>(rec.images.size());
  std::vector<LocalMotion> triplets;
  for (int i = 0; i < n; ++i)
    for (int a = 1; a < window; ++a)
      for (int b = a + 1; b < window; ++b) {
        if (!closed && i + b >= n) continue;
        triplets.push_back(MakeTriplet(
            rec, {uint32_t(i + 1), uint32_t((i + a) % n + 1), uint32_t((i + b) % n + 1)}, rng));
      }
  return triplets;
}

}  // namespace pgba::testing
