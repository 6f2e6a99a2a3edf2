// Aerial scenario: a nadir photogrammetric block flown in serpentine strips over gently
// rolling suburban terrain, 80% along-track and 60% across-track overlap.
//
// Camera: 6000 x 4000 px, f 7000 px, flown at 700 m -> 0.1 m ground sampling distance,
// 600 m (across, image x) x 400 m (along, image y) footprints, 80 m base, 240 m between
// strips. To scale to thousands of images the ground is cut into 40 m cells; each image is
// registered in the cells its footprint may cover (terrain relief included), points are
// generated cell by cell and only projected into that cell's images.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "modules/synthetic/synthetic_layout.h"
#include "modules/synthetic/synthetic_lens.h"
#include "pgba/geometry/rotation.h"

namespace pgba::synthetic {

namespace {

constexpr double kDegToRad = M_PI / 180.0;
constexpr double kAltitude = 700.0;
constexpr double kFocal = 7000.0;
constexpr int kWidth = 6000, kHeight = 4000;
constexpr double kAlongOverlap = 0.8, kAcrossOverlap = 0.6;
constexpr double kCell = 40.0;
// Terrain: two smooth waves (|h| <= 23 m) plus buildings and trees on 30% of the points.
constexpr double kGroundMin = -23.0, kGroundMax = 23.0 + 18.0;

struct Terrain {
  double phase[3];
  double Height(double x, double y) const {
    return 15.0 * std::sin(x / 350.0 + phase[0]) * std::cos(y / 450.0 + phase[1]) +
           8.0 * std::sin((x + y) / 170.0 + phase[2]);
  }
};

// Strips: 6 by default; larger blocks get about as many strips as make the block square.
int NumStrips(const SyntheticOptions& options, int n, double base, double spacing) {
  if (options.num_strips > 0) return options.num_strips;
  if (n <= 150) return std::min(6, n / 2);
  return std::max(6, static_cast<int>(std::lround(std::sqrt(n * base / spacing))));
}

// Axis-aligned ground box (x0, y0, x1, y1) that the image can see for any terrain height.
Eigen::Vector4d FootprintBox(const Camera& cam, const Pose& pose) {
  Eigen::Vector4d box(INFINITY, INFINITY, -INFINITY, -INFINITY);
  const Eigen::Vector3d C = pose.C();
  const Eigen::Matrix3d Rt = pose.R().transpose();
  for (double u : {0.0, double(cam.width)})
    for (double v : {0.0, double(cam.height)}) {
      const Eigen::Vector3d ray = Rt * cam.PixelToBearing(Eigen::Vector2d(u, v));
      for (double z : {kGroundMin, kGroundMax}) {
        const Eigen::Vector3d g = C + ray * ((z - C.z()) / ray.z());
        box.head<2>() = box.head<2>().cwiseMin(g.head<2>());
        box.tail<2>() = box.tail<2>().cwiseMax(g.head<2>());
      }
    }
  return box;
}

}  // namespace

SceneLayout MakeAerialLayout(const SyntheticOptions& options, Rng& rng) {
  SceneLayout layout;
  layout.camera.model = CameraModel::kSimplePinhole;
  layout.camera.width = kWidth;
  layout.camera.height = kHeight;
  layout.camera.params = {kFocal, kWidth / 2.0, kHeight / 2.0};
  layout.camera = WithRadialDistortion(layout.camera, options.k1, "k1");  // before any use of the camera
  const double gsd = kAltitude / kFocal;
  const double base = (1.0 - kAlongOverlap) * kHeight * gsd;     // 80 m
  const double spacing = (1.0 - kAcrossOverlap) * kWidth * gsd;  // 240 m

  const int n = options.num_images > 0 ? options.num_images : 12 * (options.num_strips > 0 ? options.num_strips : 6);
  const int strips = NumStrips(options, n, base, spacing);
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  // Nadir camera flying along +x: image x = world +y (across), image y = world +x (along),
  // optical axis = world -z. Odd strips fly back along -x (the camera turns with the plane).
  Eigen::Matrix3d nadir;
  nadir << 0, 1, 0, 1, 0, 0, 0, 0, -1;
  const Eigen::Matrix3d turn = ExpSO3(Eigen::Vector3d(0, 0, M_PI));
  for (int s = 0; s < strips; ++s) {
    const int count = n / strips + (s < n % strips ? 1 : 0);
    for (int i = 0; i < count; ++i) {
      const int along = (s % 2 == 0) ? i : count - 1 - i;
      const Eigen::Vector3d C(along * base + 2.0 * gauss(rng), s * spacing + 3.0 * gauss(rng),
                              kAltitude + 3.0 * gauss(rng));
      const Eigen::Vector3d attitude(0.5 * gauss(rng), 0.5 * gauss(rng), 1.0 * gauss(rng));
      const Eigen::Matrix3d R = ExpSO3(attitude * kDegToRad) * (s % 2 == 0 ? nadir : Eigen::Matrix3d(nadir * turn));
      char name[64];
      std::snprintf(name, sizeof(name), "strip%02d_%04d.jpg", s, i);
      layout.views.push_back({name, Pose::FromRC(R, C)});
    }
  }

  // Ground grid over the union of the footprints; each cell lists the images that may see it.
  std::vector<Eigen::Vector4d> boxes;
  Eigen::Vector4d block(INFINITY, INFINITY, -INFINITY, -INFINITY);
  for (const auto& v : layout.views) {
    boxes.push_back(FootprintBox(layout.camera, v.pose));
    block.head<2>() = block.head<2>().cwiseMin(boxes.back().head<2>());
    block.tail<2>() = block.tail<2>().cwiseMax(boxes.back().tail<2>());
  }
  const int nx = static_cast<int>(std::ceil((block[2] - block[0]) / kCell));
  const int ny = static_cast<int>(std::ceil((block[3] - block[1]) / kCell));
  std::vector<std::vector<uint32_t>> cells(static_cast<size_t>(nx) * ny);
  const auto cell_index = [&](double coord, double origin, int count) {
    return std::clamp(static_cast<int>(std::floor((coord - origin) / kCell)), 0, count - 1);
  };
  for (uint32_t v = 0; v < boxes.size(); ++v) {
    const int x0 = cell_index(boxes[v][0], block[0], nx), x1 = cell_index(boxes[v][2], block[0], nx);
    const int y0 = cell_index(boxes[v][1], block[1], ny), y1 = cell_index(boxes[v][3], block[1], ny);
    for (int iy = y0; iy <= y1; ++iy)
      for (int ix = x0; ix <= x1; ++ix) cells[static_cast<size_t>(iy) * nx + ix].push_back(v);
  }

  // Points: uniform density over the covered cells (one per 200 m^2 by default: ~1200 candidate
  // observations per image).
  size_t covered = 0;
  for (const auto& c : cells) covered += !c.empty();
  const double area = covered * kCell * kCell;
  const double density = options.num_points > 0 ? options.num_points / area : 1.0 / 200.0;
  const Terrain terrain{{2.0 * M_PI * uniform(rng), 2.0 * M_PI * uniform(rng), 2.0 * M_PI * uniform(rng)}};
  std::poisson_distribution<int> per_cell(density * kCell * kCell);
  for (int iy = 0; iy < ny; ++iy)
    for (int ix = 0; ix < nx; ++ix) {
      auto& views = cells[static_cast<size_t>(iy) * nx + ix];
      if (views.empty()) continue;
      const uint32_t group = static_cast<uint32_t>(layout.candidate_groups.size());
      layout.candidate_groups.push_back(std::move(views));
      for (int k = per_cell(rng); k > 0; --k) {
        const double x = block[0] + (ix + uniform(rng)) * kCell, y = block[1] + (iy + uniform(rng)) * kCell;
        const double above = uniform(rng) < 0.3 ? 18.0 * uniform(rng) : 0.0;  // roofs, trees
        layout.points.push_back({Eigen::Vector3d(x, y, terrain.Height(x, y) + above), Eigen::Vector3d::Zero(), group});
      }
    }
  layout.track_model = TrackModel{0.85, 10.0, 0.5, 0.5, 90.0};
  return layout;
}

}  // namespace pgba::synthetic
