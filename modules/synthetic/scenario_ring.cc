// Ring scenarios: cameras on a (slightly wavy) circle looking at an object in the middle.
//   orbit:     a Temple-like building (Tanks and Temples' Temple: 1920x1080, f 1163 px)
//              on a ground plane, seen from ~9 m.
//   longfocal: a sculpture seen from 90 m through a 1000 mm lens on a full-frame body
//              (5616x3744 px, 6.41 um pixels -> f 156,000 px, 2.06 x 1.37 degrees): nearly
//              orthographic views; the ends of the ring are withheld as a loop.
#include <cmath>
#include <cstdio>

#include "modules/synthetic/synthetic_layout.h"
#include "modules/synthetic/synthetic_lens.h"
#include "pgba/geometry/rotation.h"

namespace pgba::synthetic {

namespace {

constexpr double kDegToRad = M_PI / 180.0;

// An ellipsoid with a rough surface: points at (1 + relief * U(-1, 1)) times the surface
// radius, normals of the smooth ellipsoid.
struct Ellipsoid {
  Eigen::Vector3d centre;
  Eigen::Vector3d semi_axes;
  double relief;

  LayoutPoint Sample(Rng& rng) const {
    std::normal_distribution<double> gauss(0.0, 1.0);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    const Eigen::Vector3d u = Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng)).normalized();
    LayoutPoint p;
    p.X = centre + (1.0 + relief * uniform(rng)) * semi_axes.cwiseProduct(u);
    p.normal = u.cwiseQuotient(semi_axes).normalized();
    return p;
  }

  // Does the segment X -> C pass through the ellipsoid shrunk by `scale`?
  bool Blocks(const Eigen::Vector3d& X, const Eigen::Vector3d& C, double scale) const {
    const Eigen::Vector3d p = (X - centre).cwiseQuotient(semi_axes);
    const Eigen::Vector3d d = (C - X).cwiseQuotient(semi_axes);
    // |p + t d|^2 = scale^2 for some t in (0, 1)
    const double a = d.squaredNorm(), b = 2.0 * p.dot(d), c = p.squaredNorm() - scale * scale;
    const double disc = b * b - 4.0 * a * c;
    if (disc < 0.0) return false;
    const double t0 = (-b - std::sqrt(disc)) / (2.0 * a), t1 = (-b + std::sqrt(disc)) / (2.0 * a);
    return t1 > 0.0 && t0 < 1.0;
  }
};

std::vector<std::vector<uint32_t>> AllViewsGroup(size_t n) {
  std::vector<uint32_t> all(n);
  for (uint32_t v = 0; v < n; ++v) all[v] = v;
  return {all};
}

}  // namespace

std::vector<LayoutView> RingViews(const RingSpec& spec, int n, Rng& rng) {
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::uniform_real_distribution<double> phase(0.0, 2.0 * M_PI);
  const double wave_phase = phase(rng);
  const double step = 2.0 * M_PI / n;
  std::vector<LayoutView> views(n);
  for (int k = 0; k < n; ++k) {
    const double az = k * step + spec.azimuth_jitter * step * gauss(rng);
    const double r = spec.radius + spec.radius_jitter * gauss(rng);
    const double z = spec.height + spec.height_wave * std::sin(2.0 * az + wave_phase) + spec.height_jitter * gauss(rng);
    const Eigen::Vector3d C(r * std::cos(az), r * std::sin(az), z);
    const Eigen::Vector3d target =
        spec.target + spec.target_jitter * Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng));
    const Eigen::Matrix3d R = ExpSO3(Eigen::Vector3d(0, 0, spec.roll_deg * kDegToRad * gauss(rng))) *
                              LookAtRotation(C, target, Eigen::Vector3d::UnitZ());
    char name[64];
    std::snprintf(name, sizeof(name), spec.name_format, k);
    views[k] = {name, Pose::FromRC(R, C)};
  }
  return views;
}

SceneLayout MakeOrbitLayout(const SyntheticOptions& options, Rng& rng) {
  const int n = options.num_images > 0 ? options.num_images : 70;
  const int num_points = options.num_points > 0 ? options.num_points : 8000 * n / 70;
  SceneLayout layout;
  layout.camera.model = CameraModel::kPinhole;
  layout.camera.width = 1920;
  layout.camera.height = 1080;
  layout.camera.params = {1163.0, 1163.0, 960.0, 540.0};
  layout.camera = WithRadialDistortion(layout.camera, options.k1, "k1");  // before any use of the camera
  const RingSpec ring{"orbit_%03d.jpg", 9.0, 0.3, 3.5, 0.8, 0.2, 0.25, {0.0, 0.0, 2.3}, 0.15, 1.0};
  layout.views = RingViews(ring, n, rng);
  layout.candidate_groups = AllViewsGroup(layout.views.size());

  // The building: 6 x 4 x 5 m, sitting on the ground; a quarter of the points lie on the
  // ground around it (those can be hidden behind the building).
  const Ellipsoid building{{0.0, 0.0, 2.5}, {3.0, 2.0, 2.5}, 0.03};
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  while (static_cast<int>(layout.points.size()) < num_points) {
    if (uniform(rng) < 0.75) {
      LayoutPoint p = building.Sample(rng);
      if (p.X.z() >= 0.05) layout.points.push_back(p);
    } else {
      const double r = std::sqrt(4.0 + uniform(rng) * (7.5 * 7.5 - 4.0)), az = 2.0 * M_PI * uniform(rng);
      const Eigen::Vector2d xy(r * std::cos(az), r * std::sin(az));
      if (std::pow(xy.x() / 3.0, 2) + std::pow(xy.y() / 2.0, 2) < 1.1) continue;  // under the building
      layout.points.push_back({Eigen::Vector3d(xy.x(), xy.y(), 0.0), Eigen::Vector3d::UnitZ(), 0});
    }
  }
  // Shrunk so that the rough surface does not hide its own points.
  layout.occluded = [building](const Eigen::Vector3d& X, const Eigen::Vector3d& C) {
    return building.Blocks(X, C, 0.95);
  };
  layout.track_model = TrackModel{0.85, 9.0, 0.5, 0.5, 75.0};
  return layout;
}

SceneLayout MakeLongFocalLayout(const SyntheticOptions& options, Rng& rng) {
  const int n = options.num_images > 0 ? options.num_images : 93;
  const int num_points = options.num_points > 0 ? options.num_points : 8000 * n / 93;
  SceneLayout layout;
  layout.camera.model = CameraModel::kSimplePinhole;
  layout.camera.width = 5616;
  layout.camera.height = 3744;
  layout.camera.params = {156000.0, 2808.0, 1872.0};
  layout.camera = WithRadialDistortion(layout.camera, options.k1, "k1");  // before any use of the camera
  const RingSpec ring{"longfocal_%03d.jpg", 90.0, 1.0, 1.6, 0.15, 0.1, 0.2, {0.0, 0.0, 1.5}, 0.03, 1.0};
  layout.views = RingViews(ring, n, rng);
  layout.candidate_groups = AllViewsGroup(layout.views.size());

  // A 1.6 x 1.2 x 2.6 m sculpture on a 0.2 m pedestal; convex, so the incidence limit
  // alone decides visibility.
  const Ellipsoid sculpture{{0.0, 0.0, 1.5}, {0.8, 0.6, 1.3}, 0.03};
  while (static_cast<int>(layout.points.size()) < num_points) {
    LayoutPoint p = sculpture.Sample(rng);
    if (p.X.z() >= 0.2) layout.points.push_back(p);
  }
  layout.track_model = TrackModel{0.85, 9.0, 0.5, 0.5, 75.0};
  layout.loop_views = std::min(3, n / 4);
  return layout;
}

}  // namespace pgba::synthetic
