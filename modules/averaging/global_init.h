// Global initialisation from relative motions (the `pgba init` stage after pairs and
// triplets): rotation averaging, translation averaging and the triplets' global->local
// similarities, on the largest triplet component (InitialiseComponents: on each component).
//
//   0. unusable pairs and triplets (repeated images, non-finite values, no baseline) are
//      ignored and counted;
//   1. the triplets' relative rotations as measured: by default their local poses; the
//      sensitivity experiment (outlier_injection.h) hands in corrupted ones and keeps the
//      local poses;
//   2. keep the largest component of the triplet graph (triplets sharing an image pair);
//      images outside it are dropped and named;
//   3. pairs disagreeing with the triplets that contain them are dropped (pair_validation.h),
//      then rotation averaging over the pairs inside the component and the triplets; relative
//      rotations left as outliers by it are excluded as edges (rotation_averaging.h), and only
//      images with no inlier observation lose their rotation (and their triplets);
//   4. triplets whose local rotations disagree with the averaged ones are dropped (and the
//      component recomputed);
//   5. translation averaging, then the centres refined on the tracks with the rotations
//      held fixed (track_positioning.h);
//   6. similarities of the kept triplets; triplets whose centres do not fit are dropped (and
//      the component recomputed once more).
#pragma once

#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "averaging/pair_validation.h"
#include "averaging/rotation_averaging.h"
#include "averaging/track_positioning.h"
#include "averaging/translation_averaging.h"
#include "pgba/geometry/pose.h"
#include "pgba/scene/reconstruction.h"
#include "pgba/scene/view_graph.h"

namespace pgba {

struct GlobalInitOptions {
  PairValidationOptions pair_validation;
  RotationAveragingOptions rotation;
  TranslationAveragingOptions translation;
  TrackPositioningOptions track_positioning;
  // A triplet is dropped before translation averaging if one of its local rotations r_k
  // differs from R_k alpha^T by more than this (degrees); <= 0 keeps every triplet (the
  // sensitivity experiment hands its outliers to the global BA on purpose).
  double max_triplet_rotation_error_deg = 5.0;
  // A triplet is dropped at the end if its centres misfit its similarity by more than this
  // fraction of its local size (RMS); <= 0 keeps every triplet.
  double max_triplet_centre_error = 0.1;
  // Empty when valid, else one line naming the first field out of its valid range (the
  // ranges of io/option_ranges.cc) or breaking a rule between fields.
  std::string Check() const;
};
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(GlobalInitOptions, pair_validation, rotation, translation,
                                                track_positioning, max_triplet_rotation_error_deg, max_triplet_centre_error)

struct GlobalInitStats {
  int images_input = 0;
  int images_registered = 0;
  int pairs_input = 0;
  int triplets_input = 0;
  int triplets_kept = 0;
  // Pairs ignored for repeated images or non-finite / non-rotation values.
  int pairs_invalid = 0;
  // Pairs dropped because they disagree with the triplets (pair_validation.h).
  int pairs_inconsistent = 0;
  // Counted reasons for dropping triplets: repeated images, non-finite values or coincident
  // local centres; outside the largest component; rotation or centre misfit.
  int triplets_invalid = 0;
  int triplets_outside_component = 0;
  int triplets_rotation_outliers = 0;
  int triplets_centre_outliers = 0;
  RotationAveragingSummary rotation;
  TranslationAveragingSummary translation;
  TrackPositioningSummary track_positioning;
  double seconds_rotation = 0.0;
  double seconds_translation = 0.0;
  double seconds_similarity = 0.0;
  double seconds_total = 0.0;
};

struct GlobalInitResult {
  bool success = false;
  std::string message;
  // Global world->camera poses of the registered images.
  std::map<uint32_t, Pose> poses;
  // The kept triplets (input order), LocalMotion::global_to_local filled (paper eq. 4).
  std::vector<LocalMotion> triplets;
  // Images of `tracks` without a pose, by id and by name (same order).
  std::vector<uint32_t> dropped_image_ids;
  std::vector<std::string> images_dropped;
  GlobalInitStats stats;
};

// Throws InputError for invalid options, or if a pair or triplet names an image id that is
// not in `tracks`. Never throws for a graph that falls apart: the result then covers the
// largest component (success = false and every image dropped if there is no usable
// triplet). `rotation_measurements` (nullptr: the triplets themselves): the triplets with the
// local rotations the averaging measures, aligned with `triplets` (the sensitivity
// experiment's corrupted copies, CorruptRelativeMotions); std::invalid_argument if not aligned.
GlobalInitResult RunGlobalInitialisation(const Reconstruction& tracks, const std::vector<TwoViewGeometry>& pairs,
                                         const std::vector<LocalMotion>& triplets, const GlobalInitOptions& options,
                                         const std::vector<LocalMotion>* rotation_measurements = nullptr);

// Every component of the triplet graph (TripletComponents, connectivity.h) initialised on its
// own: RunGlobalInitialisation on the component's triplets and the pairs between its images,
// one result per component (a model of its own), the successful ones first, then by images
// registered (most first), then by component order. A result's images_dropped lists every
// image of `tracks` it does not hold. Same throws as RunGlobalInitialisation.
std::vector<GlobalInitResult> InitialiseComponents(const Reconstruction& tracks,
                                                   const std::vector<TwoViewGeometry>& pairs,
                                                   const std::vector<LocalMotion>& triplets,
                                                   const GlobalInitOptions& options,
                                                   const std::vector<LocalMotion>* rotation_measurements = nullptr);

// The stage's entry of report.json: {"seconds", "images_registered", "images_dropped": [names],
// "triplets_kept", "triplets_dropped": {reason: count}, "rotation": {...}, "translation": {...}}.
nlohmann::json GlobalInitReport(const GlobalInitResult& result);

}  // namespace pgba
