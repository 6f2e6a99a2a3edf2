// Planar scenario: a hand-held video along a flat textured wall, ETH3D planar_mono-like
// (PINHOLE 739x458 px, f 726 px, principal point off centre). The camera moves sideways
// ~5 cm per frame at 1.6-2.4 m from the wall, bobbing up and down and turning by a few
// degrees, so consecutive frames overlap by ~97%.
//
// World frame: the wall is the plane z = 0, the camera lives at z < 0 looking towards +z,
// x to the right, y down (an unrotated camera has the world axes).
#include <cmath>
#include <cstdio>

#include "modules/synthetic/synthetic_layout.h"
#include "modules/synthetic/synthetic_lens.h"
#include "pgba/geometry/rotation.h"

namespace pgba::synthetic {

namespace {
constexpr double kDegToRad = M_PI / 180.0;
}  // namespace

SceneLayout MakePlanarLayout(const SyntheticOptions& options, Rng& rng) {
  const int n = options.num_images > 0 ? options.num_images : 60;
  SceneLayout layout;
  layout.camera.model = CameraModel::kPinhole;
  layout.camera.width = 739;
  layout.camera.height = 458;
  layout.camera.params = {726.3, 726.6, 354.6, 186.5};
  layout.camera = WithRadialDistortion(layout.camera, options.k1, "k1");  // before any use of the camera

  std::normal_distribution<double> gauss(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  double phase[7];
  for (double& p : phase) p = 2.0 * M_PI * uniform(rng);
  // Smooth motion: every quantity is a slow sinusoid of the frame index (periods of 40-90
  // frames), plus a little hand shake.
  const auto wave = [&](int i, double amplitude, double period, int k) {
    return amplitude * std::sin(2.0 * M_PI * i / period + phase[k]);
  };
  Eigen::Vector4d wall(INFINITY, INFINITY, -INFINITY, -INFINITY);  // x0 y0 x1 y1 seen on the wall
  double x = 0.0;
  for (int i = 0; i < n; ++i) {
    x += 0.05 * (1.0 + wave(i, 0.3, 40.0, 0));
    const Eigen::Vector3d C(x, wave(i, 0.2, 70.0, 1), -(2.0 + wave(i, 0.4, 90.0, 2)));
    const Eigen::Vector3d angles_deg(wave(i, 3.0, 65.0, 3) + 0.05 * gauss(rng),   // pitch about x
                                     wave(i, 5.0, 55.0, 4) + 0.05 * gauss(rng),   // yaw about y
                                     wave(i, 2.0, 45.0, 5) + 0.05 * gauss(rng));  // roll about z
    const Eigen::Matrix3d R = ExpSO3(Eigen::Vector3d(0, 0, angles_deg.z() * kDegToRad)) *
                              ExpSO3(Eigen::Vector3d(angles_deg.x() * kDegToRad, 0, 0)) *
                              ExpSO3(Eigen::Vector3d(0, angles_deg.y() * kDegToRad, 0));
    const Pose pose = Pose::FromRC(R, C);
    char name[64];
    std::snprintf(name, sizeof(name), "frame_%04d.png", i);
    layout.views.push_back({name, pose});
    // Footprint on the wall: the image corners' rays meet z = 0.
    for (double u : {0.0, double(layout.camera.width)})
      for (double v : {0.0, double(layout.camera.height)}) {
        const Eigen::Vector3d ray = R.transpose() * layout.camera.PixelToBearing(Eigen::Vector2d(u, v));
        const Eigen::Vector3d g = C + ray * (-C.z() / ray.z());
        wall.head<2>() = wall.head<2>().cwiseMin(g.head<2>());
        wall.tail<2>() = wall.tail<2>().cwiseMax(g.head<2>());
      }
  }
  std::vector<uint32_t> all(n);
  for (int v = 0; v < n; ++v) all[v] = v;
  layout.candidate_groups = {all};

  // Wall texture: uniform over the seen part of the wall, 150 points per frame by default.
  const int num_points = options.num_points > 0 ? options.num_points : 150 * n;
  for (int k = 0; k < num_points; ++k) {
    const double px = wall[0] + uniform(rng) * (wall[2] - wall[0]);
    const double py = wall[1] + uniform(rng) * (wall[3] - wall[1]);
    layout.points.push_back({Eigen::Vector3d(px, py, 0.0), -Eigen::Vector3d::UnitZ(), 0});
  }
  layout.track_model = TrackModel{0.85, 3.5, 0.5, 0.5, 80.0};
  return layout;
}

}  // namespace pgba::synthetic
