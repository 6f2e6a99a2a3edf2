// SIFT keypoints in a scale space (Lowe 2004, as OpenCV and VLFeat implement it): extrema
// of the DoG over their 26 neighbours, refined to sub-pixel and sub-scale by Newton steps on
// the quadratic fit, rejected on low contrast and on edges (ratio of principal curvatures),
// and one keypoint per dominant gradient orientation (36-bin histogram, peaks >= 0.8 max).
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "features/sift_scale_space.h"

namespace pgba {

struct SiftKeypoint {
  int octave = 0;      // index into SiftScaleSpace::gaussians
  int layer = 0;       // Gaussian layer the refined extremum belongs to (1..s)
  float x = 0, y = 0;  // refined position in the octave's pixels (centres at integers)
  float sigma = 0;     // refined scale in the octave's pixels: sigma 2^((layer + ds) / s)
  float response = 0;  // |interpolated DoG| on the 0..1 grey scale
  // OpenCV's angle convention, degrees in [0, 360): 360 minus the gradient direction of the
  // image with y down, so feature files stay comparable with the OpenCV implementation.
  float angle = 0;
};

struct SiftDetectionOptions {
  double contrast_threshold = 0.02;  // on |DoG| * layers_per_octave, grey levels 0..1
  double edge_threshold = 10.0;      // maximal ratio of principal curvatures
  // > 0: the caller keeps only the max_features strongest oriented keypoints (by response,
  // which does not depend on the orientation), so orientations are computed only for the
  // extrema that can be among them: every extremum whose response reaches that of the
  // max_features-th oriented keypoint (ties included). The caller's cap then selects exactly
  // what it would from all of them. <= 0: every extremum is oriented.
  int max_features = 0;

  // Empty when valid, else the first field out of its range ("SiftDetectionOptions" in the
  // table of io/option_ranges.cc).
  std::string Check() const;
};
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(SiftDetectionOptions, contrast_threshold, edge_threshold, max_features)

// A refined extremum before its orientations: kp without an angle, and the integer sample
// (row, col of its layer) where the refinement ended, around which the orientation
// histogram is taken.
struct SiftExtremum {
  SiftKeypoint kp;
  int row, col;
};

// The extrema of one octave, every layer of it present (DoG layers 1..s, refined), appended
// in the order (layer, row, column) whatever the number of threads: the search runs in
// parallel over fixed blocks of rows whose results are concatenated in block order. Extrema
// whose refinements end on the same sample are kept once (the first), as OpenCV does.
void FindSiftExtrema(const SiftScaleSpace& ss, int octave, const SiftDetectionOptions& options,
                     std::vector<SiftExtremum>* extrema);

// Keypoints, one per dominant orientation of each extremum (Gaussian layers 1..s only), in
// the extrema's order and then by orientation peak. With options.max_features > 0 the weaker
// extrema that cannot be among the strongest max_features are left out (see above).
std::vector<SiftKeypoint> OrientSiftExtrema(const SiftScaleSpace& ss, const std::vector<SiftExtremum>& extrema,
                                            const SiftDetectionOptions& options);

}  // namespace pgba
