// A small synthetic fixture for the evaluation tests: cameras on a ring looking at a cloud of
// points, noisy observations, tracks of random length, withheld loop correspondences.
// Independent of modules/synthetic so that the evaluation is tested against a generator it
// does not share code with.
#pragma once

#include <map>
#include <random>
#include <string>
#include <vector>

#include "evaluation/loop_closure.h"
#include "pgba/geometry/rotation.h"
#include "pgba/scene/reconstruction.h"

namespace pgba::test {

struct TestScene {
  Reconstruction gt;  // true poses and points, noisy observations
  std::vector<LoopCorrespondence> loops;
};

// Camera looking from C at target (world up +z).
inline Pose LookAt(const Eigen::Vector3d& C, const Eigen::Vector3d& target) {
  const Eigen::Vector3d z = (target - C).normalized();
  const Eigen::Vector3d x = Eigen::Vector3d::UnitZ().cross(z).normalized();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Matrix3d R;
  R.row(0) = x;
  R.row(1) = y;
  R.row(2) = z;
  return Pose::FromRC(R, C);
}

inline std::string ImageName(int i) { return "img_" + std::to_string(i) + ".jpg"; }

// `num_images` views on a ring of radius 10 (heights varying) around points in [-2, 2]^3;
// each point enters each view with probability `view_probability` (tracks of >= 2 views are
// kept);
// Gaussian noise `noise_px` per coordinate. Loop correspondences: `num_loops` points seen by
// images 0 and num_images/2, observed with fresh noise, withheld from the tracks.
inline TestScene MakeTestScene(uint64_t seed, int num_images = 12, int num_points = 2000, double noise_px = 0.5,
                               int num_loops = 500, double view_probability = 0.6) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), prob(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, noise_px);
  TestScene s;
  Camera cam;
  cam.camera_id = 1;
  cam.model = CameraModel::kPinhole;
  cam.width = 1280;
  cam.height = 960;
  cam.params = {800.0, 810.0, 640.0, 480.0};
  s.gt.cameras[1] = cam;
  for (int i = 0; i < num_images; ++i) {
    const double a = 2.0 * M_PI * i / num_images;
    Image im;
    im.image_id = static_cast<uint32_t>(i + 1);
    im.name = ImageName(i);
    im.camera_id = 1;
    im.pose = LookAt(Eigen::Vector3d(10 * std::cos(a), 10 * std::sin(a), 2.0 * std::sin(3 * a)),
                     0.2 * Eigen::Vector3d(unit(rng), unit(rng), unit(rng)));
    s.gt.images[im.image_id] = im;
  }
  auto observe = [&](const Image& im, const Eigen::Vector3d& X) {
    return Eigen::Vector2d(cam.Project(im.pose.ToCamera(X)) + Eigen::Vector2d(noise(rng), noise(rng)));
  };
  for (int p = 0; p < num_points; ++p) {
    const Eigen::Vector3d X = 2.0 * Eigen::Vector3d(unit(rng), unit(rng), unit(rng));
    std::vector<TrackElement> track;
    for (auto& [id, im] : s.gt.images) {
      if (prob(rng) > view_probability) continue;
      im.points2D.push_back({observe(im, X), kNoPoint3D});
      track.push_back({id, static_cast<uint32_t>(im.points2D.size() - 1)});
    }
    if (track.size() < 2) {
      for (const auto& el : track) s.gt.images[el.image_id].points2D.pop_back();
      continue;
    }
    s.gt.AddPoint3D(X, track);
  }
  const Image& a = s.gt.images.at(1);
  const Image& b = s.gt.images.at(static_cast<uint32_t>(num_images / 2 + 1));
  for (int k = 0; k < num_loops; ++k) {
    const Eigen::Vector3d X = 2.0 * Eigen::Vector3d(unit(rng), unit(rng), unit(rng));
    s.loops.push_back({a.name, observe(a, X), b.name, observe(b, X)});
  }
  return s;
}

// A copy of `rec` with image ids shifted by `offset` and no points (an evaluated model need
// only poses; different ids check that images are matched by name).
inline Reconstruction RenumberedPosesOnly(const Reconstruction& rec, uint32_t offset) {
  Reconstruction out;
  out.cameras = rec.cameras;
  for (const auto& [id, im] : rec.images) {
    Image copy = im;
    copy.image_id = id + offset;
    for (auto& p : copy.points2D) p.point3D_id = kNoPoint3D;
    out.images[copy.image_id] = copy;
  }
  return out;
}

// Expected per-observation RMS of 2D residual norms after least-squares triangulation of
// tracks with Gaussian noise sigma per coordinate: each n-view track has 2n residuals and 3
// fitted unknowns, so E[sum ||r||^2] = (2n - 3) sigma^2, i.e. an RMS of
// sigma * sqrt(sum_t (2 n_t - 3) / sum_t n_t) over the tracks evaluated.
inline double ExpectedSigmaRms(const std::vector<int>& track_lengths, double noise_px) {
  double dof = 0.0, obs = 0.0;
  for (int n : track_lengths) {
    dof += 2.0 * n - 3.0;
    obs += n;
  }
  return noise_px * std::sqrt(dof / obs);
}

}  // namespace pgba::test
