// Synthetic scenes with exact ground truth (the test bed of every stage).
//
// GenerateSyntheticScene returns the true model (`gt`: true poses and points, noisy
// observations), the same cameras/observations/tracks with unknown poses (`input`: poses
// identity, points at the origin), and the withheld loop correspondences of scenarios
// that withhold a loop.
//
// Units are metres; every scene states its size through `extent`. Observations are what a
// feature matcher would give: a point enters the views that can see it (in front, inside
// the image, facing the camera, not occluded) only with a probability that falls with the
// change of viewpoint and scale from the view where the feature was first detected, so
// tracks have realistic, limited lengths (synthetic_tracks.cc).
//
// Generation is single-threaded from one std::mt19937_64 seeded with `seed`: the same
// options give a bit-identical scene on a given platform.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "pgba/io/loop_pairs.h"
#include "pgba/scene/reconstruction.h"

namespace pgba {

// orbit:     ~70 views on a ring around a Temple-like object (PINHOLE f 1163 px, 1920x1080).
// longfocal: 93 views on a ring around a sculpture, 1000 mm lens on a full-frame body
//            (5616x3744 px, f 156,000 px, 2.06 x 1.37 degrees field of view); every
//            correspondence between the first 3 and the last 3 views is withheld from the
//            tracks and returned as loop pairs.
// aerial:    nadir photogrammetric block, 80% along-track / 60% across-track overlap, 6
//            strips by default; scales to thousands of images (points are generated per
//            ground cell and projected only into the images whose footprint covers them).
// planar:    video along a flat wall, ETH3D planar_mono-like (PINHOLE 739x458, f 726 px).
enum class SyntheticScenario { kOrbit, kLongFocal, kAerial, kPlanar };
bool ParseSyntheticScenario(const std::string& name, SyntheticScenario* scenario);
const char* SyntheticScenarioName(SyntheticScenario scenario);

NLOHMANN_JSON_SERIALIZE_ENUM(SyntheticScenario, {{SyntheticScenario::kOrbit, "orbit"},
                                                 {SyntheticScenario::kLongFocal, "longfocal"},
                                                 {SyntheticScenario::kAerial, "aerial"},
                                                 {SyntheticScenario::kPlanar, "planar"}})

struct SyntheticOptions {
  SyntheticScenario scenario = SyntheticScenario::kOrbit;
  uint64_t seed = 1;
  // Gaussian observation noise, pixels (per coordinate). Must be >= 0.
  double noise_px = 0.5;
  // Fraction of observations replaced by uniformly random pixels in the image, in [0, 1).
  // Exactly round(outlier_fraction * observations) are replaced.
  double outlier_fraction = 0.0;
  // Number of images; 0 = the scenario's default (orbit 70, longfocal 93, aerial 6 strips
  // x 12, planar 60). Otherwise >= 3.
  int num_images = 0;
  // Number of scene points generated before track formation (points seen by fewer than two
  // views are dropped); 0 = the scenario's default, proportional to the number of images
  // (orbit 8000 per 70 images, longfocal 8000 per 93, planar 150 per image, aerial one point
  // per 200 m^2 of ground).
  int num_points = 0;
  // aerial only: number of strips; 0 = 6, or for blocks of more than 150 images about as many
  // strips as make the block square on the ground.
  int num_strips = 0;
  // Radial distortion of the true camera (synthetic_lens.h): 0 = the scenario's pinhole;
  // otherwise gt/ holds SIMPLE_RADIAL (OPENCV for two focals) with this k1 and the
  // observations are projected through it. |k1| <= 1 and invertible over the image.
  double k1 = 0.0;
  // Relative error of the calibration in input/ (the pipeline's prior): its focal is the
  // true one times (1 + focal_prior_error) and its distortion 0; gt/ keeps the truth. With
  // k1 = 0 and no error, input/ and gt/ share the camera. In [-0.5, 1].
  double focal_prior_error = 0.0;
  // Empty when valid, else one line naming the first field out of its valid range (the
  // ranges of io/option_ranges.cc) or breaking a rule between fields.
  std::string Check() const;
};
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(SyntheticOptions, scenario, seed, noise_px, outlier_fraction,
                                                num_images, num_points, num_strips, k1, focal_prior_error)

// Throws InputError naming the option if `options` is unusable.
void ValidateSyntheticOptions(const SyntheticOptions& options);

struct SyntheticScene {
  Reconstruction gt;     // the true camera (with its distortion)
  Reconstruction input;  // the prior camera (focal_prior_error, no distortion)
  std::vector<LoopCorrespondence> loop_pairs;
  // Observations of gt/input replaced by outliers (image_id, point2D_idx), sorted.
  std::vector<TrackElement> outliers;
  // Diagonal of the bounding box of the true camera centres, metres.
  double extent = 0.0;
};

// Throws InputError (via ValidateSyntheticOptions) for unusable options.
SyntheticScene GenerateSyntheticScene(const SyntheticOptions& options);

}  // namespace pgba
