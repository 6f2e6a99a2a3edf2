// sigma: the accuracy metric every method is compared by (ARCHITECTURE.md, "Evaluation
// metrics"). Every track of the observation model is triangulated with the evaluated poses
// held fixed (linear + robust Gauss-Newton, the core's TriangulateTrack) and the pixel
// reprojection errors of its observations are collected:
//   sigma_rms       = sqrt(mean ||r||^2) over observations with ||r|| < inlier_px in tracks
//                     where at least two views are under inlier_px,
//   sigma_median    = median ||r|| over all observations of triangulated tracks,
//   inlier_fraction = (#observations counted in sigma_rms) / (#evaluated observations),
//   robust_cost     = sum over evaluated observations of the Huber cost rho(||r||) at huber_px
//                     (rho(e) = e^2 up to huber_px, 2 huber_px e - huber_px^2 beyond), capped at
//                     rho(inlier_px) (an observation past it, or of a track that cannot be
//                     triangulated, costs the cap): the truncated robust reprojection cost that
//                     the point-based and the pointless BA both minimise, points eliminated.
// ||r|| is the 2D error norm in pixels. An observation is *evaluated* when its image is
// registered and its track has >= 2 registered views; observations of a track that cannot
// be triangulated (degenerate, behind a camera) are evaluated and count as outliers.
//
// The function works on (observation model, poses) so that an adjustment can call it after
// every iteration without building a Reconstruction (the convergence curves of benchmark).
#pragma once

#include <string>

#include <cstddef>
#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>

#include "pgba/geometry/pose.h"
#include "pgba/geometry/triangulation.h"
#include "pgba/scene/reconstruction.h"

namespace pgba {

struct SigmaOptions {
  // Observations with a reprojection error under this count in sigma_rms (pixels).
  double inlier_px = 4.0;
  // Huber threshold of the triangulation's Gauss-Newton refinement (pixels).
  double huber_px = 1.0;
  // Gauss-Newton iterations per track: TriangulateModel's, so that the tracks triangulated
  // here are the points of the model the mapper writes (one count in the console and report).
  int max_iterations = TriangulationOptions{}.max_iterations;
  // Empty when valid, else one line naming the first field out of its valid range (the
  // ranges of io/option_ranges.cc) or breaking a rule between fields.
  std::string Check() const;
};
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(SigmaOptions, inlier_px, huber_px, max_iterations)

struct SigmaResult {
  size_t num_tracks = 0;        // tracks with >= 2 registered views
  size_t num_triangulated = 0;  // of those, triangulated with at least two views under inlier_px
                                // (the points TriangulateModel keeps)
  size_t num_observations = 0;  // evaluated observations (all views of num_tracks)
  size_t num_inliers = 0;       // evaluated observations under inlier_px
  double rms = 0.0;             // sigma_rms, px (meaningful when num_inliers > 0)
  double median = 0.0;          // sigma_median, px (meaningful when num_triangulated > 0)
  double inlier_fraction = 0.0;
  double robust_cost = 0.0;     // px^2
  bool Computable() const { return num_inliers > 0; }
};

// Poses keyed by the observation model's image ids; an absent id is an unregistered image.
using PoseMap = std::map<uint32_t, Pose>;
// Intrinsics keyed by the observation model's image ids (e.g. a model's refined cameras).
using CameraRefMap = std::map<uint32_t, const Camera*>;

// The evaluated model's images expressed in the observation model's ids, matched by image
// NAME (the two models may number images differently). Camera pointers point into `model`.
struct RegisteredViews {
  PoseMap poses;
  CameraRefMap cameras;
};
RegisteredViews MatchImagesByName(const Reconstruction& model, const Reconstruction& obs);

// sigma of `obs`'s tracks under `poses`. Intrinsics: `cameras` where given (by obs image
// id), otherwise the observation model's. Parallel over tracks, bitwise deterministic.
SigmaResult EvaluateSigma(const Reconstruction& obs, const PoseMap& poses, const SigmaOptions& options = {},
                          const CameraRefMap* cameras = nullptr);

}  // namespace pgba
