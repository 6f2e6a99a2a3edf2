// The view graph of the tracks pipeline: image pairs sharing enough tracks, each verified
// by a calibrated relative pose (OpenGV 5-point RANSAC + refinement, modules/matching) and
// kept only with enough inliers and a baseline that is not negligible w.r.t. depth. With the
// image front end's verified geometries (`pgba run`), a pair it verified starts from its
// pose instead of a second RANSAC (PairOptions::front_end).
#pragma once

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

#include "modules/matching/relative_pose.h"
#include "pgba/scene/reconstruction.h"
#include "pgba/scene/view_graph.h"

namespace pgba {

struct PairOptions {
  // Candidate pairs share at least this many tracks.
  int min_shared_tracks = 30;
  // Candidates per image: a pair is kept if it is among the `max_pairs_per_image` pairs of
  // either of its images sharing the most tracks (0 = no limit). Bounds the work on
  // highly overlapping sets without losing any image's strongest links.
  int max_pairs_per_image = 40;
  // RANSAC + refinement (threshold_px is the inlier threshold in pixels).
  RelativePoseOptions relative_pose;
  // A verified pair has at least this many inliers and this inlier fraction.
  int min_inliers = 30;
  double min_inlier_ratio = 0.25;
  // Median triangulation angle over the inliers below which a pair is a (near) pure
  // rotation / a baseline too small w.r.t. depth, degrees.
  double min_triangulation_angle_deg = 1.0;
  // Base seed; every pair's RANSAC seed is derived from it and the image ids.
  uint64_t seed = 1;
  // What becomes of a candidate the image front end verified (only when its geometries are
  // given, i.e. `pgba run`):
  //   "refine"   (default) its pose starts the refinement on the pair's shared-track
  //              correspondences (RefineRelativePose: inliers classified with
  //              relative_pose.threshold_px, one refinement pass) and the tests above apply,
  //              without a second RANSAC; a pair that fails them is estimated by RANSAC as
  //              without a front end;
  //   "reuse"    its pose and inlier count as they are (only min_inliers and the
  //              triangulation-angle test apply): a 4x faster stage, but entry_p10's
  //              relative rotation max 0.0763 deg against 0.0752-0.0753 with RANSAC's
  //              seeds 1-3 (docs/measurement_history.md "Measured: front-end speed (issue 16)");
  //   "estimate" RANSAC on the shared tracks, as without a front end.
  std::string front_end = "refine";
  // With the front end's geometries: whether candidates it did not verify (pairs it
  // rejected, or never matched, that share tracks through third images) are estimated from
  // the tracks too. docs/measurement_history.md "Measured: front-end speed (issue 16)" has the measurement.
  bool track_only_pairs = true;
  // "" if valid, otherwise the first problem ("front_end must be one of ...").
  std::string Check() const;
};
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(PairOptions, min_shared_tracks, max_pairs_per_image, relative_pose,
                                                min_inliers, min_inlier_ratio, min_triangulation_angle_deg, seed,
                                                front_end, track_only_pairs)

struct PairStats {
  int images = 0;
  int pairs_sharing_tracks = 0;   // pairs with >= 1 shared track
  int pairs_few_shared = 0;       // below min_shared_tracks
  int pairs_capped = 0;           // dropped by max_pairs_per_image
  int pairs_track_only_skipped = 0;  // not verified by the front end, track_only_pairs false
  int pairs_estimated = 0;        // candidates examined (reused, refined or by RANSAC)
  int pairs_front_end = 0;        // of those: verified by the front end
  int pairs_reused = 0;           // of those: the front end's geometry taken as is ("reuse")
  int pairs_refined = 0;          // of those: refined from the front end's pose ("refine")
  int pairs_refine_fallback = 0;  // of the refined: failed the tests, estimated by RANSAC
  int pairs_ransac = 0;           // RANSAC runs (candidates without a usable front-end pose)
  int rejected_no_model = 0;      // RANSAC found no model
  int rejected_few_inliers = 0;   // below min_inliers / min_inlier_ratio
  int rejected_small_angle = 0;   // median triangulation angle below the threshold
  int pairs_kept = 0;
  int pairs_kept_front_end = 0;   // of the kept: the front end's geometry (reused or refined)
  int pairs_kept_ransac = 0;      // of the kept: estimated by RANSAC (pairs_kept = these two)
  int images_in_view_graph = 0;   // images with at least one kept pair
  double seconds = 0.0;
};
nlohmann::json ToJson(const PairStats& stats);

// Verified pairs of the tracks model, sorted by (image_id1, image_id2), image_id1 <
// image_id2. Parallel over pairs (TBB); the result does not depend on the thread count.
// Throws InputError for inconsistent tracks.
//
// `front_end`: the image front end's verified two-view geometries (match_images.h; either
// orientation of a pair), or null. Candidates it verified follow options.front_end, those
// it did not options.track_only_pairs. std::invalid_argument for options failing Check().
std::vector<TwoViewGeometry> EstimatePairs(const Reconstruction& tracks, const PairOptions& options,
                                           PairStats* stats = nullptr,
                                           const std::vector<TwoViewGeometry>* front_end = nullptr);

}  // namespace pgba
