// The synthetic setting the accuracy targets are stated on (docs/benchmarks.md): a
// `pgba synth` scene with 0.5 px Gaussian noise per coordinate and 2% of the observations
// replaced by random pixels (gross outliers).
#pragma once

#include <cstdint>

#include "synthetic/synthetic_scene.h"

namespace pgba::test {

// num_images 0: the scenario's default count.
inline SyntheticScene AcceptanceScene(SyntheticScenario scenario, int num_images, uint64_t seed) {
  SyntheticOptions o;
  o.scenario = scenario;
  o.num_images = num_images;
  o.seed = seed;
  o.noise_px = 0.5;
  o.outlier_fraction = 0.02;
  return GenerateSyntheticScene(o);
}

}  // namespace pgba::test
