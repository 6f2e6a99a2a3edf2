#include "modules/synthetic/aerial_block.h"

#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <random>

#include "modules/synthetic/lens_remap.h"
#include "modules/synthetic/procedural_texture.h"
#include "modules/synthetic/seed_mix.h"
#include "modules/synthetic/sensor_noise.h"
#include "modules/synthetic/synthetic_lens.h"
#include "pgba/geometry/rotation.h"
#include "pgba/io/colmap_text.h"
#include "pgba/util/atomic_file.h"
#include "pgba/util/error.h"
#include "pgba/util/timer.h"

namespace pgba {
namespace {

using synthetic::TexturedQuad;
constexpr double kDegToRad = M_PI / 180.0;
constexpr double kTile = 64.0;  // metres; one texture per tile
// Texels of 0.8 ground samples: at 2x supersampling a rendered sample covers 0.5 ground
// samples, so the texture is magnified ~1.6x before the box filter, not blurred much,
// and the ground of a 1,000-image block fits in ~1 GB.
constexpr double kTexelPerSample = 0.8;
constexpr double kAttitudeSdDeg = 2.0;
// Footprints include the buildings' tops only approximately (they are computed on z = 0);
// the ground reaches this much beyond the union of the footprints.
constexpr double kGroundMargin = 30.0;
// Stream indices of MixSeed: textures of tiles and walls, the buildings of a tile, noise.
constexpr uint64_t kBuildingStream = 0xB011D1ULL, kNoiseStream = 0xA5A5A5A5ULL;

double Shade(const Eigen::Vector3d& u, const Eigen::Vector3d& v) {
  const Eigen::Vector3d light = Eigen::Vector3d(0.4, -0.3, 0.87).normalized();
  return 0.65 + 0.35 * std::abs(u.cross(v).normalized().dot(light));
}

TexturedQuad MakeQuad(const Eigen::Vector3d& origin, const Eigen::Vector3d& u, const Eigen::Vector3d& v, double texel,
                      uint64_t seed) {
  TexturedQuad q;
  q.origin = origin;
  q.u_axis = u;
  q.v_axis = v;
  const int w = std::max(1, static_cast<int>(std::lround(u.norm() / texel)));
  const int h = std::max(1, static_cast<int>(std::lround(v.norm() / texel)));
  q.texture = synthetic::MakeProceduralTexture(w, h, seed);
  q.texture.convertTo(q.texture, CV_8UC3, Shade(u, v));
  return q;
}

struct QuadSpec {
  Eigen::Vector3d origin, u, v;
};

// Walls and roof of a box building on the ground.
void AddBuilding(const Eigen::Vector2d& centre, double half_x, double half_y, double height, double yaw,
                 std::vector<QuadSpec>* out) {
  const Eigen::Matrix3d Rz = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Vector3d ex = Rz * Eigen::Vector3d(2 * half_x, 0, 0), ey = Rz * Eigen::Vector3d(0, 2 * half_y, 0);
  const Eigen::Vector3d up(0, 0, height);
  const Eigen::Vector3d corner = Eigen::Vector3d(centre.x(), centre.y(), 0.0) - 0.5 * ex - 0.5 * ey;
  out->push_back({corner, ex, up});
  out->push_back({corner + ey, ex, up});
  out->push_back({corner, ey, up});
  out->push_back({corner + ex, ey, up});
  out->push_back({corner + up, ex, ey});
}

// Ground-plane bounding box (x0, y0, x1, y1) of a quad.
Eigen::Vector4d QuadBox(const TexturedQuad& q) {
  Eigen::Vector4d b(INFINITY, INFINITY, -INFINITY, -INFINITY);
  for (const Eigen::Vector3d& X : {q.origin, Eigen::Vector3d(q.origin + q.u_axis), Eigen::Vector3d(q.origin + q.v_axis),
                                   Eigen::Vector3d(q.origin + q.u_axis + q.v_axis)}) {
    b.head<2>() = b.head<2>().cwiseMin(X.head<2>());
    b.tail<2>() = b.tail<2>().cwiseMax(X.head<2>());
  }
  return b;
}

Eigen::Vector4d PolygonBox(const synthetic::GroundPolygon& p) {
  Eigen::Vector4d b(INFINITY, INFINITY, -INFINITY, -INFINITY);
  for (const Eigen::Vector2d& x : p) {
    b.head<2>() = b.head<2>().cwiseMin(x);
    b.tail<2>() = b.tail<2>().cwiseMax(x);
  }
  return b;
}

bool BoxesMeet(const Eigen::Vector4d& a, const Eigen::Vector4d& b, double margin) {
  return a[0] - margin <= b[2] && b[0] - margin <= a[2] && a[1] - margin <= b[3] && b[1] - margin <= a[3];
}

}  // namespace

AerialBlockOptions DefaultAerialBlockOptions() {
  AerialBlockOptions o;
  o.image.num_images = 1000;
  o.image.width = 1024;
  o.image.height = 768;
  return o;
}

void ValidateAerialBlockOptions(const AerialBlockOptions& o) {
  ValidateRenderedSceneOptions(o.image);
  if (o.image.num_images < 4)
    ThrowInputError("--images", 0, "aerial: must be >= 4, got " + std::to_string(o.image.num_images));
  if (o.image.num_images > 20000) ThrowInputError("--images", 0, "aerial: must be <= 20000");
  if (o.strips < 0 || o.strips > o.image.num_images / 2)
    ThrowInputError("--strips", 0, "must be 0 (automatic) or 1..images/2 (at least 2 images per strip)");
  if (!(o.forward_overlap >= 0.5 && o.forward_overlap <= 0.9))
    ThrowInputError("--forward-overlap", 0, "must be in [0.5, 0.9]");
  if (!(o.side_overlap >= 0.2 && o.side_overlap <= 0.8)) ThrowInputError("--side-overlap", 0, "must be in [0.2, 0.8]");
  if (!(o.ground_sample_m > 0.001 && o.ground_sample_m < 10.0))
    ThrowInputError("--ground-sample", 0, "must be in (0.001, 10) metres");
}

AerialBlock MakeAerialBlock(const AerialBlockOptions& options) {
  ValidateAerialBlockOptions(options);
  Timer timer;
  const RenderedSceneOptions& io = options.image;
  AerialBlock block;

  const Camera cam = RenderedCamera(io);
  const double f = cam.params[0];  // every model RenderedCamera returns starts with the focal
  block.gt.cameras[1] = cam;
  block.calibration = synthetic::FocalPrior(cam, io.focal_prior_error);

  // Flight plan: strips along world +x; image y along the strip, image x across it.
  const double gsd = options.ground_sample_m;
  block.altitude = f * gsd;
  const double base = (1.0 - options.forward_overlap) * io.height * gsd;
  const double spacing = (1.0 - options.side_overlap) * io.width * gsd;
  const int n = io.num_images;
  int strips = options.strips;
  if (strips == 0) strips = std::clamp(static_cast<int>(std::lround(std::sqrt(n * base / spacing))), 1, n / 2);
  block.strips = strips;
  Eigen::Matrix3d nadir;  // world -> camera: x_cam = y_world, y_cam = x_world, z_cam = -z_world
  nadir << 0, 1, 0, 1, 0, 0, 0, 0, -1;
  const Eigen::Matrix3d turn = ExpSO3(Eigen::Vector3d(0, 0, M_PI));  // odd strips fly back
  std::mt19937_64 rng(options.image.seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  Eigen::AlignedBox3d centres;
  uint32_t id = 0;
  for (int s = 0; s < strips; ++s) {
    const int count = n / strips + (s < n % strips ? 1 : 0);
    for (int i = 0; i < count; ++i) {
      const int along = (s % 2 == 0) ? i : count - 1 - i;
      const Eigen::Vector3d C(along * base + 0.05 * base * gauss(rng), s * spacing + 0.03 * spacing * gauss(rng),
                              block.altitude * (1.0 + 0.01 * gauss(rng)));
      const Eigen::Vector3d attitude = kAttitudeSdDeg * kDegToRad * Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng));
      const Eigen::Matrix3d R = ExpSO3(attitude) * (s % 2 == 0 ? nadir : Eigen::Matrix3d(nadir * turn));
      Image& im = block.gt.images[++id];
      im.image_id = id;
      char name[64];
      std::snprintf(name, sizeof(name), "strip%02d_%04d.png", s, i);
      im.name = name;
      im.camera_id = 1;
      im.pose = Pose::FromRC(R, C);
      centres.extend(C);
      block.footprints.push_back(synthetic::GroundFootprint(cam, im.pose, 0.0));
    }
  }
  block.extent = centres.diagonal().norm();

  // Ground tiles over the union of the footprints, then buildings tile by tile.
  Eigen::Vector4d ground(INFINITY, INFINITY, -INFINITY, -INFINITY);
  for (const auto& fp : block.footprints) {
    const Eigen::Vector4d b = PolygonBox(fp);
    ground.head<2>() = ground.head<2>().cwiseMin(b.head<2>());
    ground.tail<2>() = ground.tail<2>().cwiseMax(b.tail<2>());
  }
  ground.head<2>().array() -= kGroundMargin;
  ground.tail<2>().array() += kGroundMargin;
  const int nx = static_cast<int>(std::ceil((ground[2] - ground[0]) / kTile));
  const int ny = static_cast<int>(std::ceil((ground[3] - ground[1]) / kTile));
  std::vector<QuadSpec> specs;
  for (int iy = 0; iy < ny; ++iy)
    for (int ix = 0; ix < nx; ++ix)
      specs.push_back({Eigen::Vector3d(ground[0] + ix * kTile, ground[1] + iy * kTile, 0.0),
                       Eigen::Vector3d(kTile, 0, 0), Eigen::Vector3d(0, kTile, 0)});
  for (int t = 0; t < nx * ny; ++t) {
    // Each tile's buildings from its own stream: the town does not change when the block grows.
    std::mt19937_64 trng(synthetic::MixSeed(options.image.seed ^ kBuildingStream, static_cast<uint64_t>(t)));
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    const int count = std::poisson_distribution<int>(1.5)(trng);
    for (int b = 0; b < count; ++b) {
      const Eigen::Vector2d c = specs[t].origin.head<2>() + kTile * Eigen::Vector2d(u01(trng), u01(trng));
      const double hx = 4.0 + 8.0 * u01(trng), hy = 4.0 + 8.0 * u01(trng), h = 4.0 + 11.0 * u01(trng);
      AddBuilding(c, hx, hy, h, 0.5 * M_PI * u01(trng), &specs);
    }
  }
  const double texel = kTexelPerSample * gsd;
  block.quads.resize(specs.size());
  tbb::parallel_for(size_t(0), specs.size(), [&](size_t i) {
    block.quads[i] =
        MakeQuad(specs[i].origin, specs[i].u, specs[i].v, texel, synthetic::MixSeed(options.image.seed, i));
  });
  block.lens = std::make_shared<synthetic::LensRenderer>(cam, io.supersampling);
  block.texture_seconds = timer.Seconds();
  return block;
}

cv::Mat RenderAerialImage(const AerialBlock& block, const AerialBlockOptions& options, size_t k) {
  const Image& im = block.gt.images.at(static_cast<uint32_t>(k + 1));
  // Only the quads near the footprint: the others cost a projection each, and a far one
  // whose corners fall behind a tilted camera would be rasterised over the whole image.
  const Eigen::Vector4d fp = PolygonBox(block.footprints[k]);
  std::vector<TexturedQuad> near;
  for (const TexturedQuad& q : block.quads)
    if (BoxesMeet(QuadBox(q), fp, kGroundMargin)) near.push_back(q);  // cv::Mat copies share texels
  cv::Mat img = block.lens->Render(near, im.pose);
  synthetic::AddSensorNoise(&img, options.image.image_noise, synthetic::MixSeed(options.image.seed ^ kNoiseStream, k));
  return img;
}

std::vector<std::pair<uint32_t, uint32_t>> OverlappingPairs(const AerialBlock& block, double min_overlap) {
  const size_t n = block.footprints.size();
  std::vector<Eigen::Vector4d> boxes(n);
  for (size_t i = 0; i < n; ++i) boxes[i] = PolygonBox(block.footprints[i]);
  std::vector<std::pair<uint32_t, uint32_t>> pairs;
  for (size_t i = 0; i < n; ++i)
    for (size_t j = i + 1; j < n; ++j)
      if (BoxesMeet(boxes[i], boxes[j], 0.0) &&
          synthetic::FootprintOverlap(block.footprints[i], block.footprints[j]) >= min_overlap)
        pairs.emplace_back(static_cast<uint32_t>(i), static_cast<uint32_t>(j));
  return pairs;
}

double WriteAerialBlock(const AerialBlock& block, const AerialBlockOptions& options, const std::string& dir) {
  namespace fs = std::filesystem;
  Timer timer;
  const fs::path out(dir);
  fs::create_directories(out);
  const size_t n = block.gt.images.size();
  {
    StagedDirectory staged(out / "images");  // a stale image of a larger block would join the set
    tbb::parallel_for(size_t(0), n, [&](size_t k) {
      std::vector<uchar> buf;
      if (!cv::imencode(".png", RenderAerialImage(block, options, k), buf))
        throw std::runtime_error("PNG encoding failed");
      WriteStringAtomically(staged.path() / block.gt.images.at(static_cast<uint32_t>(k + 1)).name,
                            std::string(buf.begin(), buf.end()));
    });
    staged.Commit();
  }
  const double seconds = timer.Seconds();
  Reconstruction calibration;
  calibration.cameras[block.calibration.camera_id] = block.calibration;
  WriteColmapCamerasFile(calibration, (out / "cameras.txt").string());
  WriteColmapText(block.gt, (out / "gt").string());
  std::string overlap;
  for (const auto& [i, j] : OverlappingPairs(block, 0.1)) {
    char row[32];
    std::snprintf(row, sizeof(row), " %.3f\n", synthetic::FootprintOverlap(block.footprints[i], block.footprints[j]));
    overlap += block.gt.images.at(i + 1).name + " " + block.gt.images.at(j + 1).name + row;
  }
  WriteStringAtomically(out / "overlap.txt", overlap);
  std::error_code ec;
  fs::remove(out / "loop.txt", ec);  // a room's ring order, stale here
  return seconds;
}

// ValidateAerialBlockOptions's rules (they name the CLI flags), as a message.
std::string AerialBlockOptions::Check() const { return synthetic::ValidationMessage(ValidateAerialBlockOptions, *this); }

}  // namespace pgba
