// Procedural, feature-rich and non-repetitive colour textures for rendered synthetic scenes
// (rendered_scene.h). What SIFT needs from a surface: blob-like structure at every scale
// (difference-of-Gaussian extrema), corners and edges that give distinctive descriptors, and
// no repetition (a repeated motif makes the ratio test reject, or worse, accept, the wrong
// neighbour). A texture is the sum of
//   1. multi-scale value noise: per octave, a grid of uniform random values upsampled with
//      bicubic interpolation, octave amplitudes falling with frequency (1/f-like),
//   2. random filled ellipses of log-uniformly distributed size and random colour,
//   3. random "text": strings of random characters with OpenCV's Hershey fonts at random
//      sizes and colours (high-frequency, corner-rich, never twice the same string),
//   4. random line segments,
// then band-limited by a small Gaussian blur so that rendering does not alias. Everything
// is drawn from one cv::RNG seeded by `seed`: the same arguments give the same texels.
#pragma once

#include <string>

#include <cstdint>
#include <opencv2/core.hpp>

namespace pgba::synthetic {

struct ProceduralTextureOptions {
  // Largest noise cell, texels; octaves halve it down to 4 texels.
  int largest_cell = 256;
  // Mean number of ellipses / text strings / segments per 10,000 texels.
  double blobs_per_10k = 4.0;
  double texts_per_10k = 0.5;
  double lines_per_10k = 0.5;
  // Ellipse semi-axes are log-uniform in [min_blob, max_blob] texels.
  double min_blob = 3.0;
  double max_blob = 60.0;
  // Standard deviation of the final blur, texels (band limit: features need ~2 texels).
  double blur_sigma = 0.7;
  // Empty when valid, else one line naming the first field out of its valid range (the
  // ranges of io/option_ranges.cc) or breaking a rule between fields.
  std::string Check() const;
};

// A width x height CV_8UC3 (BGR) texture. InputError-free: sizes must be >= 1 (asserted).
cv::Mat MakeProceduralTexture(int width, int height, uint64_t seed,
                              const ProceduralTextureOptions& options = ProceduralTextureOptions());

}  // namespace pgba::synthetic
