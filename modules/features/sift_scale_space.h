// The SIFT scale space (Lowe 2004): octaves of Gaussian-blurred layers, each octave half the
// size of the previous one, and their differences (DoG). Built with the parallel filters of
// gaussian_blur.h; the same layout as OpenCV's and VLFeat's so their parameters carry over.
#pragma once

#include <functional>
#include <opencv2/core.hpp>
#include <vector>

namespace pgba {

struct SiftScaleSpace {
  int layers_per_octave = 3;  // s: scales per octave where extrema are sought
  double sigma = 1.6;         // blur of each octave's first layer, in that octave's pixels
  bool upsampled = false;     // octave 0 is the input doubled (first octave -1)
  // gaussians[o] has s + 3 layers; DoG layer i of octave o is gaussians[o][i+1] - [i],
  // computed by the detector where it reads it (sift_keypoints.cc), not stored. Once the
  // scale space is built only layers 1..s remain (the orientations' and descriptors'); the
  // others, which only the detector reads, are empty.
  std::vector<std::vector<cv::Mat>> gaussians;
  // Octave 0's detection-only layers, released after its detection: the later octaves'
  // layers are views into them (all later octaves together need 2/3 of their size), so a
  // scale space takes 6 layers of octave 0 instead of 8 in fresh memory.
  std::vector<cv::Mat> storage;
  int num_octaves() const { return static_cast<int>(gaussians.size()); }
};

// Called once octave o is complete (all its s + 3 layers), before its detection-only layers
// are released: where the detector runs on it.
using SiftOctaveCallback = std::function<void(const SiftScaleSpace& ss, int octave)>;

// Scale space of an 8-bit image (grey levels 0..255 kept as floats). upsample: start on the
// doubled image (the input is assumed blurred by 0.5 px, 1 px once doubled), as OpenCV and
// COLMAP's default; otherwise at the input resolution. Octaves stop when the smaller side
// would fall below 8 px (OpenCV's count: round(log2(min side)) - 2 octaves). Every octave's
// pixels are the same whatever happens to the memory in between.
SiftScaleSpace BuildSiftScaleSpace(const cv::Mat& gray8u, bool upsample, const SiftOctaveCallback& on_octave,
                                   int layers_per_octave = 3, double sigma = 1.6);

}  // namespace pgba
