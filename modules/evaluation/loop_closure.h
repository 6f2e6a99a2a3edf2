// Loop-closure error (ARCHITECTURE.md, "Evaluation metrics"): correspondences between a
// pair of images that the method never saw (withheld, e.g. between the first and the last
// views of a ring) are triangulated from the two final poses; drift around the loop shows
// up as reprojection error that sigma, computed on the tracks the method did see, hides.
// Both observations of each correspondence enter the RMS and the median (pixels, no
// inlier cut-off: a loop that does not close must show).
#pragma once

#include <cstddef>
#include <vector>

#include "pgba/io/loop_pairs.h"
#include "pgba/scene/reconstruction.h"

namespace pgba {

struct LoopClosureResult {
  size_t num_correspondences = 0;  // all withheld correspondences
  size_t num_unregistered = 0;     // skipped: an image is absent from the model
  size_t num_failed = 0;           // rays do not meet in front of both cameras
  size_t num_evaluated = 0;        // triangulated; 2 residuals each
  double rms = 0.0;                // px, meaningful when num_evaluated > 0
  double median = 0.0;
  bool Computable() const { return num_evaluated > 0; }
};

// Images are looked up by name in `model` (poses and intrinsics both from the model).
LoopClosureResult EvaluateLoopClosure(const Reconstruction& model, const std::vector<LoopCorrespondence>& loops);

}  // namespace pgba
