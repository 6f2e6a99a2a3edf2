// Points of a model from its tracks and a set of known poses: every track with at least two
// posed views is triangulated (linear + robust Gauss-Newton, TriangulateTrack); outlier
// observations stay in their track (the evaluation's sigma skips them). It writes the points of
// `init/`, `sparse/` and each benchmark method's model.
#pragma once

#include <cstdint>
#include <map>

#include "pgba/geometry/pose.h"
#include "pgba/geometry/triangulation.h"
#include "pgba/scene/reconstruction.h"

namespace pgba {

// A copy of `tracks` restricted to the images of `poses`, with those poses and the
// triangulated points (ids and tracks kept; failed tracks removed; Point3D::error = mean
// inlier residual in px). Parallel over tracks, deterministic.
Reconstruction TriangulateModel(const Reconstruction& tracks, const std::map<uint32_t, Pose>& poses,
                                const TriangulationOptions& options = {});

}  // namespace pgba
