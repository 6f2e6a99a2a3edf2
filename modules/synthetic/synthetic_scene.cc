// Common machinery of the synthetic scenes: option checks, scenario dispatch, and the
// conversion of a scenario's geometry into observed models (noise, outliers, the gt and
// input reconstructions).
#include "modules/synthetic/synthetic_scene.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "modules/synthetic/synthetic_layout.h"
#include "modules/synthetic/synthetic_lens.h"
#include "pgba/util/error.h"
#include "pgba/util/logging.h"

namespace pgba {

namespace {

constexpr const char* kWhat = "synthetic scene";

struct ScenarioEntry {
  SyntheticScenario scenario;
  const char* name;
};
constexpr ScenarioEntry kScenarios[] = {{SyntheticScenario::kOrbit, "orbit"},
                                        {SyntheticScenario::kLongFocal, "longfocal"},
                                        {SyntheticScenario::kAerial, "aerial"},
                                        {SyntheticScenario::kPlanar, "planar"}};

// Observed tracks of every point of the layout, in point order.
std::vector<synthetic::SyntheticTrack> ObserveTracks(const synthetic::SceneLayout& layout, double noise_px,
                                                     synthetic::Rng& rng) {
  std::normal_distribution<double> noise(0.0, 1.0);
  std::vector<synthetic::SyntheticTrack> tracks;
  for (uint32_t i = 0; i < layout.points.size(); ++i) {
    const auto sightings = synthetic::VisibleSightings(layout, layout.points[i]);
    const auto chosen = synthetic::SelectTrackViews(sightings, layout.track_model, rng);
    if (chosen.size() < 2) continue;
    synthetic::SyntheticTrack t;
    t.point = i;
    for (const auto& s : chosen) {
      t.views.push_back(s.view);
      const double dx = noise(rng), dy = noise(rng);
      t.pixels.push_back(s.pixel + noise_px * Eigen::Vector2d(dx, dy));
    }
    tracks.push_back(std::move(t));
  }
  return tracks;
}

// gt model: camera 1, images 1..N in view order, one point per track (ids 1..T).
Reconstruction AssembleModel(const synthetic::SceneLayout& layout,
                             const std::vector<synthetic::SyntheticTrack>& tracks) {
  Reconstruction rec;
  Camera cam = layout.camera;
  cam.camera_id = 1;
  rec.cameras[1] = cam;
  for (uint32_t v = 0; v < layout.views.size(); ++v) {
    Image& im = rec.images[v + 1];
    im.image_id = v + 1;
    im.name = layout.views[v].name;
    im.camera_id = 1;
    im.pose = layout.views[v].pose;
  }
  for (size_t k = 0; k < tracks.size(); ++k) {
    const uint64_t id = k + 1;
    Point3D& p = rec.points3D.emplace_hint(rec.points3D.end(), id, Point3D{})->second;
    p.point3D_id = id;
    p.xyz = layout.points[tracks[k].point].X;
    for (size_t e = 0; e < tracks[k].views.size(); ++e) {
      Image& im = rec.images.at(tracks[k].views[e] + 1);
      p.track.push_back({im.image_id, static_cast<uint32_t>(im.points2D.size())});
      im.points2D.push_back({tracks[k].pixels[e], static_cast<int64_t>(id)});
    }
  }
  return rec;
}

// Replaces exactly round(fraction * observations) observations, chosen uniformly without
// replacement (selection sampling, Knuth's algorithm S), by uniform pixels in the image.
std::vector<TrackElement> InjectOutliers(double fraction, synthetic::Rng& rng, Reconstruction* rec) {
  const size_t total = rec->NumObservations();
  size_t wanted = static_cast<size_t>(std::llround(fraction * static_cast<double>(total)));
  std::vector<TrackElement> outliers;
  if (wanted == 0) return outliers;
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  size_t remaining = total;
  for (const auto& [pid, p] : rec->points3D) {
    for (const TrackElement& e : p.track) {
      const double u = uniform(rng);
      if (u * static_cast<double>(remaining--) < static_cast<double>(wanted)) {
        --wanted;
        Image& im = rec->images.at(e.image_id);
        const Camera& cam = rec->CameraOf(im);
        im.points2D[e.point2D_idx].xy = Eigen::Vector2d(uniform(rng) * cam.width, uniform(rng) * cam.height);
        outliers.push_back(e);
      }
    }
  }
  std::sort(outliers.begin(), outliers.end(), [](const TrackElement& a, const TrackElement& b) {
    return a.image_id != b.image_id ? a.image_id < b.image_id : a.point2D_idx < b.point2D_idx;
  });
  return outliers;
}

// COLMAP's per-point error: mean reprojection error (px) of its observations.
void SetPointErrors(Reconstruction* rec) {
  for (auto& [pid, p] : rec->points3D) {
    double sum = 0.0;
    for (const TrackElement& e : p.track) {
      const Image& im = rec->images.at(e.image_id);
      sum += (rec->CameraOf(im).Project(im.pose.ToCamera(p.xyz)) - im.points2D[e.point2D_idx].xy).norm();
    }
    p.error = sum / static_cast<double>(p.track.size());
  }
}

// Poses and points unknown: the same observations and tracks, the prior cameras.
Reconstruction MakeInput(const Reconstruction& gt, double focal_prior_error) {
  Reconstruction input = gt;
  for (auto& [id, cam] : input.cameras) cam = synthetic::FocalPrior(cam, focal_prior_error);
  for (auto& [id, im] : input.images) im.pose = Pose();
  for (auto& [id, p] : input.points3D) {
    p.xyz.setZero();
    p.error = -1.0;
  }
  return input;
}

double CentreExtent(const Reconstruction& rec) {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = Eigen::Vector3d::Constant(-INFINITY);
  for (const auto& [id, im] : rec.images) {
    lo = lo.cwiseMin(im.pose.C());
    hi = hi.cwiseMax(im.pose.C());
  }
  return rec.images.empty() ? 0.0 : (hi - lo).norm();
}

}  // namespace

bool ParseSyntheticScenario(const std::string& name, SyntheticScenario* scenario) {
  for (const auto& e : kScenarios)
    if (name == e.name) {
      *scenario = e.scenario;
      return true;
    }
  return false;
}

const char* SyntheticScenarioName(SyntheticScenario scenario) {
  for (const auto& e : kScenarios)
    if (scenario == e.scenario) return e.name;
  return "unknown";
}

void ValidateSyntheticOptions(const SyntheticOptions& o) {
  if (!std::isfinite(o.noise_px) || o.noise_px < 0.0)
    ThrowInputError(kWhat, 0, "noise (noise_px) must be a finite number >= 0 px, got " + std::to_string(o.noise_px));
  if (!(o.outlier_fraction >= 0.0 && o.outlier_fraction < 1.0))
    ThrowInputError(kWhat, 0,
                    "outlier fraction (outlier_fraction) must be in [0, 1), got " + std::to_string(o.outlier_fraction));
  if (o.num_images != 0 && o.num_images < 3)
    ThrowInputError(kWhat, 0, "number of images (num_images) must be >= 3, got " + std::to_string(o.num_images));
  if (o.num_images > 1000000)
    ThrowInputError(kWhat, 0, "number of images (num_images) is unreasonably large: " + std::to_string(o.num_images));
  if (o.num_points < 0)
    ThrowInputError(kWhat, 0, "number of points (num_points) must be >= 0, got " + std::to_string(o.num_points));
  if (o.num_strips < 0)
    ThrowInputError(kWhat, 0, "number of strips (num_strips) must be >= 0, got " + std::to_string(o.num_strips));
  if (o.num_strips > 0 && o.scenario != SyntheticScenario::kAerial)
    ThrowInputError(kWhat, 0, "number of strips (num_strips) only applies to the aerial scenario");
  if (o.num_strips > 0 && o.num_images > 0 && o.num_images < 2 * o.num_strips)
    ThrowInputError(kWhat, 0,
                    "aerial: " + std::to_string(o.num_images) + " images cannot fill " + std::to_string(o.num_strips) +
                        " strips of at least 2 images");
  synthetic::ValidateLensOptions(o.k1, "k1", o.focal_prior_error, "focal_prior_error");
  bool known = false;
  for (const auto& e : kScenarios) known |= e.scenario == o.scenario;
  if (!known) ThrowInputError(kWhat, 0, "unknown scenario");
}

SyntheticScene GenerateSyntheticScene(const SyntheticOptions& options) {
  ValidateSyntheticOptions(options);
  synthetic::Rng rng(options.seed);
  synthetic::SceneLayout layout;
  switch (options.scenario) {
    case SyntheticScenario::kOrbit:
      layout = synthetic::MakeOrbitLayout(options, rng);
      break;
    case SyntheticScenario::kLongFocal:
      layout = synthetic::MakeLongFocalLayout(options, rng);
      break;
    case SyntheticScenario::kAerial:
      layout = synthetic::MakeAerialLayout(options, rng);
      break;
    case SyntheticScenario::kPlanar:
      layout = synthetic::MakePlanarLayout(options, rng);
      break;
  }
  SyntheticScene scene;
  std::vector<synthetic::SyntheticTrack> tracks = ObserveTracks(layout, options.noise_px, rng);
  synthetic::WithholdLoop(layout, &tracks, &scene.loop_pairs);
  scene.gt = AssembleModel(layout, tracks);
  scene.outliers = InjectOutliers(options.outlier_fraction, rng, &scene.gt);
  SetPointErrors(&scene.gt);
  scene.input = MakeInput(scene.gt, options.focal_prior_error);
  scene.extent = CentreExtent(scene.gt);
  size_t unobserved = 0;
  for (const auto& [id, im] : scene.gt.images) unobserved += im.points2D.empty();
  if (unobserved > 0)
    PGBA_LOG_WARN << SyntheticScenarioName(options.scenario) << ": " << unobserved << " of " << scene.gt.images.size()
                  << " images have no observations (too few images or points for this scenario)";
  return scene;
}

// ValidateSyntheticOptions's rules (they name the CLI flags), as a message.
std::string SyntheticOptions::Check() const { return synthetic::ValidationMessage(ValidateSyntheticOptions, *this); }

}  // namespace pgba
