#include "modules/synthetic/rendered_scene.h"

#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "modules/synthetic/lens_remap.h"
#include "modules/synthetic/procedural_texture.h"
#include "modules/synthetic/quad_renderer.h"
#include "modules/synthetic/seed_mix.h"
#include "modules/synthetic/sensor_noise.h"
#include "modules/synthetic/synthetic_layout.h"
#include "modules/synthetic/synthetic_lens.h"
#include "pgba/io/colmap_text.h"
#include "pgba/util/atomic_file.h"
#include "pgba/util/error.h"
#include "pgba/util/timer.h"

namespace pgba {
namespace {

using synthetic::TexturedQuad;

// A rectangle before texturing: texel size in metres (texture resolution).
struct QuadSpec {
  Eigen::Vector3d origin, u, v;
  double texel;
};

// Texel sizes: at f = 0.8 x 640 px and 2x supersampling a rendered sample covers ~2.5 mm on
// the boxes (2.4 m away) and ~6-12 mm on the far walls; the textures match that, so they
// are neither blown up into blur nor heavily minified.
constexpr double kRoomTexel = 0.006;
constexpr double kBoxTexel = 0.003;
// The default cameras never see the ceiling (their highest ray meets it beyond the walls);
// it only shows with a wide field of view, so it gets a coarse texture (a quarter of the
// texels: texturing is most of the rendering time).
constexpr double kCeilingTexel = 0.012;

// Four sides and the top of a box standing on z = z0, rotated by `yaw` about the vertical.
void AddBox(const Eigen::Vector2d& centre, double half_x, double half_y, double z0, double z1, double yaw_deg,
            std::vector<QuadSpec>* quads) {
  const Eigen::Matrix3d Rz = Eigen::AngleAxisd(yaw_deg * M_PI / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Vector3d c(centre.x(), centre.y(), z0);
  const Eigen::Vector3d ex = Rz * Eigen::Vector3d(2 * half_x, 0, 0), ey = Rz * Eigen::Vector3d(0, 2 * half_y, 0);
  const Eigen::Vector3d up(0, 0, z1 - z0);
  const Eigen::Vector3d corner = c - 0.5 * ex - 0.5 * ey;  // (-x, -y) bottom corner
  quads->push_back({corner, ex, up, kBoxTexel});
  quads->push_back({corner + ey, ex, up, kBoxTexel});
  quads->push_back({corner, ey, up, kBoxTexel});
  quads->push_back({corner + ex, ey, up, kBoxTexel});
  quads->push_back({corner + up, ex, ey, kBoxTexel});
}

std::vector<QuadSpec> RoomGeometry() {
  constexpr double X = 4.0, Y = 3.5, H = 3.0;  // half extents and height, metres
  const Eigen::Vector3d o(-X, -Y, 0.0), ex(2 * X, 0, 0), ey(0, 2 * Y, 0), ez(0, 0, H);
  std::vector<QuadSpec> q = {
      {o, ex, ey, kRoomTexel},                  // floor
      {o + ez, ex, ey, kCeilingTexel},          // ceiling
      {o, ex, ez, kRoomTexel},                  // wall y = -Y
      {o + ey, ex, ez, kRoomTexel},             // wall y = +Y
      {o, ey, ez, kRoomTexel},                  // wall x = -X
      {o + ex, ey, ez, kRoomTexel},             // wall x = +X
  };
  // Boxes at many depths, so that any two overlapping views share non-coplanar structure:
  // the matches of a pair that only sees one plane (the floor) fit two relative poses
  // equally well (the two-fold ambiguity of a homography), and RANSAC may pick the wrong
  // one. Measured on the default 20 views: with the two central boxes alone, 11 of 100
  // verified pairs had rotation errors above 5 degrees.
  AddBox({0.0, 0.0}, 0.7, 0.5, 0.0, 0.9, 20.0, &q);       // a table-sized box in the middle
  AddBox({-0.15, 0.1}, 0.3, 0.25, 0.9, 1.35, -35.0, &q);  // a smaller one on top
  // Low boxes between the middle and the ring, below the cameras' lines of sight.
  AddBox({1.25, -0.85}, 0.25, 0.2, 0.0, 0.5, 10.0, &q);
  AddBox({-1.15, 1.05}, 0.3, 0.22, 0.0, 0.4, -25.0, &q);
  AddBox({-0.9, -1.2}, 0.18, 0.18, 0.0, 0.7, 40.0, &q);
  AddBox({0.6, 1.35}, 0.22, 0.3, 0.0, 0.3, 65.0, &q);
  // Furniture along the walls, outside the ring, standing out from the background walls.
  AddBox({3.6, 1.4}, 0.35, 0.8, 0.0, 1.8, 0.0, &q);
  AddBox({-3.4, -2.9}, 0.45, 0.4, 0.0, 1.0, 0.0, &q);
  AddBox({-1.0, 3.1}, 0.9, 0.3, 0.0, 0.8, 0.0, &q);
  AddBox({1.8, -3.15}, 0.6, 0.25, 0.0, 1.3, 0.0, &q);
  AddBox({-3.65, 1.2}, 0.3, 0.5, 0.0, 2.2, 0.0, &q);
  return q;
}

// An object on a table-sized stand in a plain room: the walls, floor and ceiling one grey each
// (texel 0), so that every feature lies on the object, which the ring of cameras sees all
// around; its parts at several depths and angles, so that no pair sees one plane only.
std::vector<QuadSpec> ObjectGeometry() {
  constexpr double X = 3.0, Y = 3.0, H = 2.6;
  const Eigen::Vector3d o(-X, -Y, 0.0), ex(2 * X, 0, 0), ey(0, 2 * Y, 0), ez(0, 0, H);
  std::vector<QuadSpec> q = {{o, ex, ey, 0.0}, {o + ez, ex, ey, 0.0}, {o, ex, ez, 0.0},
                             {o + ey, ex, ez, 0.0}, {o, ey, ez, 0.0},  {o + ex, ey, ez, 0.0}};
  std::vector<QuadSpec> parts;
  AddBox({0.0, 0.0}, 0.22, 0.16, 0.0, 0.45, 15.0, &parts);     // the body
  AddBox({0.05, -0.02}, 0.12, 0.1, 0.45, 0.7, -30.0, &parts);  // a smaller part on top
  AddBox({-0.2, 0.18}, 0.07, 0.09, 0.0, 0.3, 50.0, &parts);    // one at its side
  AddBox({0.22, -0.2}, 0.06, 0.06, 0.0, 0.18, 5.0, &parts);    // and a low one in front
  q.insert(q.end(), parts.begin(), parts.end());
  return q;
}

// View-independent (Lambertian) shading from one distant light, so that faces differ in
// brightness as in a photograph; |cos| because the quads' normals are not oriented.
double Shade(const QuadSpec& q) {
  const Eigen::Vector3d light = Eigen::Vector3d(0.4, -0.3, 0.87).normalized();
  return 0.65 + 0.35 * std::abs(q.u.cross(q.v).normalized().dot(light));
}

TexturedQuad Texture(const QuadSpec& spec, uint64_t seed) {
  TexturedQuad q;
  q.origin = spec.origin;
  q.u_axis = spec.u;
  q.v_axis = spec.v;
  if (spec.texel <= 0) {  // plain: one grey, shaded like the others
    q.texture = cv::Mat(2, 2, CV_8UC3, cv::Scalar::all(150.0 * Shade(spec)));
    return q;
  }
  const int w = std::max(1, static_cast<int>(std::lround(spec.u.norm() / spec.texel)));
  const int h = std::max(1, static_cast<int>(std::lround(spec.v.norm() / spec.texel)));
  q.texture = synthetic::MakeProceduralTexture(w, h, seed);
  q.texture.convertTo(q.texture, CV_8UC3, Shade(spec));
  return q;
}

}  // namespace

void ValidateRenderedSceneOptions(const RenderedSceneOptions& o) {
  const auto fail = [](const char* what, const std::string& msg) { ThrowInputError(what, 0, msg); };
  if (o.num_images < 3) fail("--images", "must be >= 3, got " + std::to_string(o.num_images));
  if (o.width < 32 || o.height < 32 || o.width > 8192 || o.height > 8192)
    fail("--width/--height", "must be within 32..8192 pixels");
  if (!(o.focal_px >= 0.0 && std::isfinite(o.focal_px))) fail("--focal", "must be a finite number > 0 (0 = default)");
  if (o.supersampling < 1 || o.supersampling > 4) fail("--supersampling", "must be 1..4");
  if (!(o.image_noise >= 0.0 && o.image_noise < 64.0)) fail("--image-noise", "must be in [0, 64) grey levels");
  synthetic::ValidateLensOptions(o.k1, "--k1", o.focal_prior_error, "--focal-prior-error");
}

Camera RenderedCamera(const RenderedSceneOptions& options) {
  Camera cam;
  cam.camera_id = 1;
  cam.model = CameraModel::kPinhole;
  cam.width = options.width;
  cam.height = options.height;
  const double f = options.focal_px > 0 ? options.focal_px : 0.8 * options.width;
  cam.params = {f, f, 0.5 * options.width, 0.5 * options.height};
  return synthetic::WithRadialDistortion(cam, options.k1, "--k1");
}

namespace {

// The scene's quads textured and seen from `ring`: gt, calibration, loop and images.
RenderedScene RenderRing(const RenderedSceneOptions& options, const synthetic::RingSpec& ring,
                         const std::vector<QuadSpec>& specs) {
  ValidateRenderedSceneOptions(options);
  Timer timer;
  RenderedScene scene;

  const Camera cam = RenderedCamera(options);
  scene.gt.cameras[1] = cam;
  scene.calibration = synthetic::FocalPrior(cam, options.focal_prior_error);

  synthetic::Rng rng(options.seed);
  const std::vector<synthetic::LayoutView> views = synthetic::RingViews(ring, options.num_images, rng);
  Eigen::AlignedBox3d box;
  for (size_t k = 0; k < views.size(); ++k) {
    Image& im = scene.gt.images[k + 1];
    im.image_id = static_cast<uint32_t>(k + 1);
    im.name = views[k].name;
    im.camera_id = 1;
    im.pose = views[k].pose;
    scene.loop.push_back(im.name);
    box.extend(im.pose.C());
  }
  scene.extent = box.diagonal().norm();

  std::vector<TexturedQuad> quads(specs.size());
  tbb::parallel_for(size_t(0), specs.size(),
                    [&](size_t i) { quads[i] = Texture(specs[i], synthetic::MixSeed(options.seed, i)); });

  scene.images.resize(views.size());
  const synthetic::LensRenderer lens(cam, options.supersampling);
  tbb::parallel_for(size_t(0), views.size(), [&](size_t k) {
    cv::Mat img = lens.Render(quads, views[k].pose);
    synthetic::AddSensorNoise(&img, options.image_noise, synthetic::MixSeed(options.seed ^ 0xA5A5A5A5ULL, k));
    scene.images[k] = img;
  });
  scene.seconds = timer.Seconds();
  return scene;
}

}  // namespace

RenderedScene RenderRoomScene(const RenderedSceneOptions& options) {
  // The ring: radius 2.4 m (the boxes' far corner is ~0.9 m from the centre, the walls 3.5 m).
  const synthetic::RingSpec ring{"room_%03d.png", 2.4, 0.08, 1.5, 0.12, 0.04, 0.15, {0.0, 0.0, 0.7}, 0.08, 2.0};
  return RenderRing(options, ring, RoomGeometry());
}

RenderedScene RenderObjectScene(const RenderedSceneOptions& options) {
  // The ring: radius 1.3 m around the object (0.5 m across), looking at its middle from above.
  const synthetic::RingSpec ring{"object_%03d.png", 1.3, 0.04, 0.9, 0.08, 0.02, 0.1, {0.0, 0.0, 0.3}, 0.03, 2.0};
  return RenderRing(options, ring, ObjectGeometry());
}

void WriteRenderedScene(const RenderedScene& scene, const std::string& dir) {
  namespace fs = std::filesystem;
  const fs::path out(dir);
  fs::create_directories(out);
  {
    // Replaced as a whole: a stale image of an earlier, larger scene would join the set.
    StagedDirectory staged(out / "images");
    std::vector<std::string> encoded(scene.images.size());
    tbb::parallel_for(size_t(0), scene.images.size(), [&](size_t k) {
      std::vector<uchar> buf;
      if (!cv::imencode(".png", scene.images[k], buf)) throw std::runtime_error("PNG encoding failed");
      encoded[k] = std::string(buf.begin(), buf.end());
    });
    for (size_t k = 0; k < encoded.size(); ++k)
      WriteStringAtomically(staged.path() / scene.gt.images.at(static_cast<uint32_t>(k + 1)).name, encoded[k]);
    staged.Commit();
  }
  Reconstruction calibration;
  calibration.cameras[scene.calibration.camera_id] = scene.calibration;
  WriteColmapCamerasFile(calibration, (out / "cameras.txt").string());
  WriteColmapText(scene.gt, (out / "gt").string());
  std::string loop;
  for (const std::string& name : scene.loop) loop += name + "\n";
  WriteStringAtomically(out / "loop.txt", loop);
}

// ValidateRenderedSceneOptions's rules (they name the CLI flags), as a message.
std::string RenderedSceneOptions::Check() const { return synthetic::ValidationMessage(ValidateRenderedSceneOptions, *this); }

}  // namespace pgba
