// Internal to the synthetic module: what a scenario generator produces (cameras, true
// poses, true points and which views may see them) and the machinery that turns it into a
// scene (visibility, track formation, noise, outliers, loop withholding).
//
// A scenario only describes geometry; every statistical choice about observations lives in
// synthetic_scene.cc and synthetic_tracks.cc, so all scenarios are observed the same way.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "modules/synthetic/synthetic_scene.h"
#include "pgba/geometry/pose.h"
#include "pgba/scene/camera.h"

namespace pgba::synthetic {

using Rng = std::mt19937_64;

// How feature matching limits tracks (synthetic_tracks.cc). A point's track is seeded in a
// reference view drawn uniformly among the views that see it; another view joins with
// probability
//   detect_probability * exp(-theta^2 / (2 s^2)) * exp(-ln(d / d_ref)^2 / (2 sigma_log_scale^2))
// where theta is the angle between the two viewing rays at the point, d the distances to
// the point, and s = sigma_angle_deg * exp(N(0, sigma_angle_spread)) drawn per point (some
// features are far more distinctive than others, giving a long tail of long tracks).
struct TrackModel {
  double detect_probability = 0.85;
  double sigma_angle_deg = 9.0;
  double sigma_angle_spread = 0.5;
  double sigma_log_scale = 0.5;
  // A surface seen more obliquely than this (angle between normal and viewing ray) yields
  // no feature.
  double max_incidence_deg = 75.0;
};

struct LayoutView {
  std::string name;
  Pose pose;
};

struct LayoutPoint {
  Eigen::Vector3d X = Eigen::Vector3d::Zero();
  // Outward surface normal; zero = no incidence limit.
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  // Index into SceneLayout::candidate_groups: the views that may see the point.
  uint32_t group = 0;
};

struct SceneLayout {
  Camera camera;  // shared by every view (camera_id 1)
  std::vector<LayoutView> views;
  std::vector<LayoutPoint> points;
  // Candidate views per spatial group (sorted view indices). Small scenes use one group
  // holding every view; the aerial block buckets the ground so that a point is only
  // projected into the images whose footprint may cover it.
  std::vector<std::vector<uint32_t>> candidate_groups;
  // True if the segment from point X to centre C is blocked by the scene (null = never).
  std::function<bool(const Eigen::Vector3d& X, const Eigen::Vector3d& C)> occluded;
  TrackModel track_model;
  // Correspondences between the first and the last `loop_views` views are withheld from
  // the tracks and returned as loop pairs (0 = none).
  int loop_views = 0;
};

// Scenario generators (one file each). `options` is validated; num_images/num_points may be
// 0 (= scenario default).
SceneLayout MakeOrbitLayout(const SyntheticOptions& options, Rng& rng);
SceneLayout MakeLongFocalLayout(const SyntheticOptions& options, Rng& rng);
SceneLayout MakeAerialLayout(const SyntheticOptions& options, Rng& rng);
SceneLayout MakePlanarLayout(const SyntheticOptions& options, Rng& rng);

// A view of a point that passed the visibility tests.
struct Sighting {
  uint32_t view = 0;
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();  // true projection
  Eigen::Vector3d ray = Eigen::Vector3d::Zero();    // unit vector point -> centre
  double distance = 0.0;
};

// A track before assembly: views in increasing order, noisy pixels.
struct SyntheticTrack {
  uint32_t point = 0;  // index into SceneLayout::points
  std::vector<uint32_t> views;
  std::vector<Eigen::Vector2d> pixels;
};

// Views of `layout` that see point p: in front, inside the image, within the incidence
// limit, not occluded; in increasing view order.
std::vector<Sighting> VisibleSightings(const SceneLayout& layout, const LayoutPoint& point);

// The subset of `sightings` that feature matching would link into one track (see
// TrackModel); may be shorter than 2.
std::vector<Sighting> SelectTrackViews(const std::vector<Sighting>& sightings, const TrackModel& model, Rng& rng);

// Withholds the loop: every track holding views of both ends (first and last `loop_views`
// of `num_views`) contributes all its (end-A view, end-B view) correspondences to `pairs`
// and is split into its first and second half of the view order, so that no track links the
// two ends; halves shorter than 2 are dropped.
void WithholdLoop(const SceneLayout& layout, std::vector<SyntheticTrack>* tracks,
                  std::vector<LoopCorrespondence>* pairs);

// Views on a (slightly wavy, jittered) horizontal circle about the z axis, each looking at
// `target` (jittered) with image x horizontal; view k at azimuth about k * 360 / n degrees.
// Shared by the ring scenarios and the rendered room (rendered_scene.cc).
struct RingSpec {
  const char* name_format;  // printf format of the image name, one %d (view index)
  double radius;            // metres
  double radius_jitter;     // std dev, metres
  double height;            // mean camera height, metres
  double height_wave;       // amplitude of a smooth height variation around the ring
  double height_jitter;     // std dev, metres
  double azimuth_jitter;    // std dev, fraction of the angular step
  Eigen::Vector3d target;   // look-at point
  double target_jitter;     // std dev, metres
  double roll_deg;          // std dev of the roll about the optical axis
};
std::vector<LayoutView> RingViews(const RingSpec& spec, int n, Rng& rng);

// Camera looking from C at `target`, image x axis horizontal (perpendicular to `up`), image
// y axis pointing down.
Eigen::Matrix3d LookAtRotation(const Eigen::Vector3d& C, const Eigen::Vector3d& target, const Eigen::Vector3d& up);

}  // namespace pgba::synthetic
