// Synthetic scenes with exact ground truth (the test bed of every stage).
//
// GenerateSyntheticScene returns the true model (`gt`: true poses and points, noisy
// observations), the same cameras/observations/tracks with unknown poses (`input`: poses
// identity, points at the origin), and the withheld loop correspondences of scenarios
// that withhold a loop.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "pgba/scene/reconstruction.h"

namespace pgba {

enum class SyntheticScenario { kOrbit, kLongFocal, kAerial, kPlanar };
bool ParseSyntheticScenario(const std::string& name, SyntheticScenario* scenario);
const char* SyntheticScenarioName(SyntheticScenario scenario);

struct SyntheticOptions {
  SyntheticScenario scenario = SyntheticScenario::kOrbit;
  uint64_t seed = 1;
  // Gaussian observation noise, pixels (per coordinate).
  double noise_px = 0.5;
  // Fraction of observations replaced by uniformly random pixels in the image.
  double outlier_fraction = 0.0;
  // Number of images; 0 = the scenario's default (orbit 70, longfocal 93, aerial 6 strips
  // x 12, planar 60).
  int num_images = 0;
  // Number of scene points; 0 = the scenario's default.
  int num_points = 0;
};

// A withheld correspondence between two images (pixels), for the loop-closure metric.
struct LoopCorrespondence {
  std::string name_i;
  Eigen::Vector2d xy_i;
  std::string name_j;
  Eigen::Vector2d xy_j;
};

struct SyntheticScene {
  Reconstruction gt;
  Reconstruction input;
  std::vector<LoopCorrespondence> loop_pairs;
};

SyntheticScene GenerateSyntheticScene(const SyntheticOptions& options);

}  // namespace pgba
