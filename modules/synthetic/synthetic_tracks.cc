// Visibility and track formation: which views see a point, and which of those a feature
// matcher would actually link into its track.
#include <algorithm>
#include <cmath>

#include "modules/synthetic/synthetic_layout.h"

namespace pgba::synthetic {

namespace {
constexpr double kDegToRad = M_PI / 180.0;
// Projections closer than this to the image border are not detected (a descriptor needs
// support around the keypoint; also keeps noisy pixels essentially inside the image).
constexpr double kBorderPx = 1.0;
// A distortion polynomial turns round beyond some radius: a point far outside the field of
// view (barrel k1 < 0: beyond 1 / sqrt(3 |k1|)) would land back inside the image. It is
// seen only if its pixel undistorts to its own ray.
bool ProjectsUnfolded(const Camera& cam, const Eigen::Vector3d& x_cam, const Eigen::Vector2d& pixel) {
  if (cam.model == CameraModel::kPinhole || cam.model == CameraModel::kSimplePinhole) return true;
  Eigen::Vector2d u;
  return cam.UndistortPixel(pixel, &u) && (u - x_cam.head<2>() / x_cam.z()).norm() < 1e-6 * (1.0 + u.norm());
}

}  // namespace

Eigen::Matrix3d LookAtRotation(const Eigen::Vector3d& C, const Eigen::Vector3d& target, const Eigen::Vector3d& up) {
  const Eigen::Vector3d z = (target - C).normalized();
  const Eigen::Vector3d x = z.cross(up).normalized();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Matrix3d R;  // rows: camera axes in world coordinates (world -> camera)
  R.row(0) = x.transpose();
  R.row(1) = y.transpose();
  R.row(2) = z.transpose();
  return R;
}

std::vector<Sighting> VisibleSightings(const SceneLayout& layout, const LayoutPoint& point) {
  std::vector<Sighting> out;
  const Camera& cam = layout.camera;
  const double cos_max_incidence = std::cos(layout.track_model.max_incidence_deg * kDegToRad);
  const bool has_normal = point.normal.squaredNorm() > 0.0;
  for (uint32_t v : layout.candidate_groups[point.group]) {
    const Pose& pose = layout.views[v].pose;
    const Eigen::Vector3d x_cam = pose.ToCamera(point.X);
    if (x_cam.z() <= 1e-9) continue;
    const Eigen::Vector2d pixel = cam.Project(x_cam);
    if (!ProjectsUnfolded(cam, x_cam, pixel)) continue;
    if (pixel.x() < kBorderPx || pixel.y() < kBorderPx || pixel.x() > cam.width - kBorderPx ||
        pixel.y() > cam.height - kBorderPx)
      continue;
    const Eigen::Vector3d C = pose.C();
    const Eigen::Vector3d to_centre = C - point.X;
    const double distance = to_centre.norm();
    const Eigen::Vector3d ray = to_centre / distance;
    if (has_normal && point.normal.dot(ray) < cos_max_incidence) continue;
    if (layout.occluded && layout.occluded(point.X, C)) continue;
    out.push_back({v, pixel, ray, distance});
  }
  return out;
}

std::vector<Sighting> SelectTrackViews(const std::vector<Sighting>& sightings, const TrackModel& model, Rng& rng) {
  if (sightings.size() < 2) return {};
  std::uniform_int_distribution<size_t> pick(0, sightings.size() - 1);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const Sighting& ref = sightings[pick(rng)];
  // Per-point distinctiveness: the angular width over which this feature still matches.
  const double sigma_angle = model.sigma_angle_deg * kDegToRad * std::exp(model.sigma_angle_spread * normal(rng));
  std::vector<Sighting> track;
  for (const Sighting& s : sightings) {
    const double u = uniform(rng);  // drawn for every view: the stream does not depend on branches
    if (s.view == ref.view) {
      track.push_back(s);
      continue;
    }
    const double angle = std::acos(std::clamp(s.ray.dot(ref.ray), -1.0, 1.0));
    const double log_scale = std::log(s.distance / ref.distance);
    const double p = model.detect_probability * std::exp(-0.5 * std::pow(angle / sigma_angle, 2)) *
                     std::exp(-0.5 * std::pow(log_scale / model.sigma_log_scale, 2));
    if (u < p) track.push_back(s);
  }
  return track;
}

void WithholdLoop(const SceneLayout& layout, std::vector<SyntheticTrack>* tracks,
                  std::vector<LoopCorrespondence>* pairs) {
  const uint32_t n = static_cast<uint32_t>(layout.views.size());
  const uint32_t k = static_cast<uint32_t>(layout.loop_views);
  if (k == 0 || 2 * k >= n) return;
  const auto in_first = [&](uint32_t v) { return v < k; };
  const auto in_last = [&](uint32_t v) { return v >= n - k; };
  std::vector<SyntheticTrack> kept;
  kept.reserve(tracks->size());
  for (SyntheticTrack& t : *tracks) {
    const bool has_first = std::any_of(t.views.begin(), t.views.end(), in_first);
    const bool has_last = std::any_of(t.views.begin(), t.views.end(), in_last);
    if (!has_first || !has_last) {
      kept.push_back(std::move(t));
      continue;
    }
    for (size_t a = 0; a < t.views.size(); ++a) {
      if (!in_first(t.views[a])) continue;
      for (size_t b = 0; b < t.views.size(); ++b)
        if (in_last(t.views[b]))
          pairs->push_back({layout.views[t.views[a]].name, t.pixels[a], layout.views[t.views[b]].name, t.pixels[b]});
    }
    // Split at the middle of the view order: the first k views fall in the first half and
    // the last k in the second (2k < n), so neither half links the two ends.
    SyntheticTrack halves[2];
    for (size_t e = 0; e < t.views.size(); ++e) {
      SyntheticTrack& h = halves[t.views[e] < n / 2 ? 0 : 1];
      h.point = t.point;
      h.views.push_back(t.views[e]);
      h.pixels.push_back(t.pixels[e]);
    }
    for (SyntheticTrack& h : halves)
      if (h.views.size() >= 2) kept.push_back(std::move(h));
  }
  *tracks = std::move(kept);
}

}  // namespace pgba::synthetic
