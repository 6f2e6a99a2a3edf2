// Estimation of one triplet with a consistent scale, and its refinement by a triplet BA.
//
//   1. Base pair: of the three verified pairs, the one with the best inliers x angle score;
//      its first view a is put at the identity, the second b at |C_b| = 1 (the pair's unit
//      translation).
//   2. Tracks seen by a and b are triangulated with those two poses (this fixes the scale
//      of the triplet); the third view c is placed by OpenGV absolute pose (P3P in RANSAC +
//      nonlinear refinement) on the ones it also sees. Its rotation must agree with the
//      pairs (a, c) and (b, c) (max_rotation_cycle_deg).
//      Open triplet (one of the three pairs did not verify; see TripletOptions::open_triplets):
//      c takes the rotation and direction of its pair with the hinge view, and the length of
//      that baseline is the median ratio of the depths of the tracks seen by all three views.
//   3. Every track seen by >= 2 of the 3 views is triangulated robustly; observations off by
//      more than outlier_threshold_px are dropped.
//   4. Triplet BA (BundleAdjust: 3 poses + points, Huber), gauge a fixed and |C_b - C_a|
//      held, repeated after removing observations off by more than outlier_threshold_px.
//   5. Checks: tracks >= min_tracks, median triangulation angle >= the threshold (else near
//      pure rotation), rms <= max_rms_px, BA converged.
//   6. The local frame is then re-expressed in the canonical gauge of the triplet artefact:
//      image_ids ascending, local_poses[0] = identity, |C(local_poses[1])| = 1.
#pragma once

#include <array>
#include <cstdint>

#include "modules/triplets/track_index.h"
#include "modules/triplets/triplet_options.h"
#include "pgba/scene/view_graph.h"

namespace pgba {

struct TripletEstimate {
  TripletRejection rejection = TripletRejection::kNone;
  LocalMotion triplet;                    // valid if rejection == kNone
  int num_tracks_all_views = 0;           // tracks seen by all three views after the BA
  double median_triangulation_angle_deg = 0.0;
  double score = 0.0;                     // TripletOptions::score_angle_deg
  int ba_iterations = 0;
  // Self-calibration (TripletOptions::refine_intrinsics): whether the BA estimated the
  // intrinsics, and their largest standard deviation (IntrinsicsUncertainty::max_stddev_px).
  bool intrinsics_freed = false;
  double intrinsics_max_sd_px = 0.0;
};

// `image_ids` ascending; pairs[0], pairs[1], pairs[2] are the verified geometries of the
// pairs (ids[0], ids[1]), (ids[0], ids[2]), (ids[1], ids[2]); at most one may be null (an
// open triplet). Deterministic for a seed.
TripletEstimate EstimateTriplet(const TrackIndex& index, const std::array<uint32_t, 3>& image_ids,
                                const std::array<const TwoViewGeometry*, 3>& pairs, const TripletOptions& options,
                                uint64_t seed);

// x_to = R x_from + t of a verified pair, in either direction (|t| = 1).
Pose RelativePoseOfPair(const TwoViewGeometry& pair, uint32_t from, uint32_t to);

// Selection score: tracks seen by all three views x min(1, angle / score_angle_deg).
double TripletScore(int num_tracks_all_views, double median_angle_deg, const TripletOptions& options);

}  // namespace pgba
