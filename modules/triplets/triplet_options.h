// Options and statistics of the triplet stage (enumeration, estimation, triplet BA,
// selection). Defaults suit 0.5-1 px noise and a few percent outlier observations.
#pragma once

#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>

#include "modules/triplets/absolute_pose.h"
#include "pgba/optim/bundle_adjuster.h"

namespace pgba {

struct TripletOptions {
  // --- selection ---
  // Bound the triplet count on highly overlapping sets (triplet_selection.h): at most
  // about `max_triplets_per_image` per image, best first, plus what connectivity needs.
  bool selection = true;
  int max_triplets_per_image = 6;
  // Rounds of select -> estimate -> replace the failures by the next best candidates.
  int max_selection_rounds = 20;
  // --- candidates ---
  // Triangles of the view graph whose pairwise rotations do not close (angle of
  // R_ki^T R_kj R_ji, degrees) are inconsistent and skipped before estimation.
  double max_rotation_cycle_deg = 3.0;
  // Open triplets: paths a - b - c of two verified pairs whose third pair (a, c) did not
  // verify. Triangles alone break a ring at a wide gap or a chain whose skip pairs do not
  // match (the triplet graph then falls into pieces joined by single images, whose relative
  // scale nothing measures). Where that happens, and only there (open candidates are made
  // for pairs in different triplet-graph components or in none), open triplets bridge the
  // pieces. Their one extra unknown, the length of the hinge's second baseline, is measured
  // on the tracks seen by all three views: a median needs few (3 tolerate one bad track);
  // how well they measure it is what the triplet's local hessian then tells the global BA.
  bool open_triplets = true;
  int open_min_tracks_all_views = 3;
  // --- estimation ---
  // Third view placed by absolute pose on the points triangulated from the best pair
  // (only an initialisation for the triplet BA: a loose threshold and few inliers suffice).
  AbsolutePoseOptions absolute_pose = [] {
    AbsolutePoseOptions o;
    o.threshold_px = 4.0;
    o.min_inliers = 10;
    return o;
  }();
  // Observations farther than this from their reprojection are outliers (triangulation,
  // triplet BA), pixels.
  double outlier_threshold_px = 4.0;
  // Tracks whose rays meet at less than this (degrees) are not used (depth unobservable).
  double min_track_angle_deg = 0.25;
  // Triplet BA (points eliminated first, Huber loss, view gauge described in triplets.h).
  // num_threads is forced to 1: triplets run in parallel.
  BundleAdjusterOptions bundle_adjuster = [] {
    BundleAdjusterOptions o;
    o.solver.max_iterations = 200;
    return o;
  }();
  // Self-calibration in the triplet BA: the focal and distortion coefficients of the
  // triplet's cameras (IntrinsicsOptions' switches) become unknowns of its BA, a copy per
  // triplet (only its relative poses leave the stage). PointlessMapper::Solve turns it on whenever the
  // final adjustments estimate intrinsics (section intrinsics): under a prior 3% long with an
  // unmodelled k = -0.08 the initial relative rotations err by 5.4 deg held, 0.11 deg freed
  // (tests/triplets/triplet_self_calibration_test.cc).
  bool refine_intrinsics = false;
  // ... but a camera with a prior focal (a calibration file given as a prior, EXIF:
  // Camera::has_prior_focal_length) only in the triplets that determine it: its intrinsics are
  // freed when each free parameter's standard deviation (IntrinsicsUncertainty, at the initial
  // solution, for 1 px noise) moves the farthest image corner by at most this many pixels;
  // otherwise (and wherever the freed BA does not converge) they are held at the current
  // estimate, which the global adjustments refine from all views. A focal that is only the
  // 1.2 max(w, h) guess is freed in every triplet (wherever the BA converges): even a triplet
  // that sees it poorly corrects a guess 2x short (temple_sparse_ring). Measured (largest sd
  // at the corner per px of noise): Strecha triplets (fountain, herzjesu, FoV 58 deg) 2-18 px,
  // a synthetic ring triplet at FoV 77 deg 26 px (tests/triplets/intrinsics_uncertainty_test.cc),
  // the temple ring (FoV 24 deg) 96-497 px: there the freed focals scattered over 1232-1865 px
  // (truth 1523), 14 freed BAs ran out of iterations and the view graph split (13/16 images);
  // held: 16/16. Must be > 0 (1e9: always free).
  double intrinsics_max_sd_px = 50.0;
  // --- rejection ---
  int min_tracks = 30;                       // tracks seen by >= 2 of the 3 views after the BA
  double max_rms_px = 1.5;                   // reprojection RMS after the BA
  double min_triangulation_angle_deg = 1.0;  // median over tracks: below = near pure rotation
  // Score = tracks seen by all three views x min(1, median triangulation angle / this).
  double score_angle_deg = 5.0;
  uint64_t seed = 1;
  // Empty if usable, else the first problem naming the key.
  std::string Check() const;
};
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(TripletOptions, selection, max_triplets_per_image,
                                                max_selection_rounds, max_rotation_cycle_deg, open_triplets,
                                                open_min_tracks_all_views, absolute_pose,
                                                outlier_threshold_px, min_track_angle_deg, bundle_adjuster, refine_intrinsics,
                                                intrinsics_max_sd_px,
                                                min_tracks,
                                                max_rms_px, min_triangulation_angle_deg, score_angle_deg, seed)

// Why a triplet was not kept.
enum class TripletRejection { kNone, kRotationCycle, kTooFewTracks, kInitFailed, kNotConverged, kHighRms, kDegenerate };
const char* TripletRejectionName(TripletRejection r);

struct TripletStats {
  int candidates = 0;                 // triangles of the view graph
  int open_candidates = 0;            // open triplets tried as bridges (TripletOptions::open_triplets)
  int open_selected = 0;              // of the returned triplets
  int rejected_rotation_cycle = 0;    // before estimation
  int rejected_few_tracks_precheck = 0;  // before estimation: too few shared tracks
  int estimated = 0;                  // triplet estimations run
  int rejected_too_few_tracks = 0;
  int rejected_init_failed = 0;       // absolute pose of the third view failed
  int rejected_not_converged = 0;
  int intrinsics_freed = 0;           // of the returned triplets: intrinsics estimated (refine_intrinsics)
  int rejected_high_rms = 0;
  int rejected_degenerate = 0;        // near pure rotation / baseline tiny w.r.t. depth
  int selection_rounds = 0;
  int selected_unestimated = 0;       // selected but not estimated when max_selection_rounds ran out
  int selected = 0;                   // triplets returned
  int images_in_view_graph = 0;
  int images_covered = 0;             // images in at least one returned triplet
  int triplet_graph_components = 0;   // of the returned triplets (adjacency: shared pair)
  double median_rms_px = 0.0;
  double seconds = 0.0;
};
nlohmann::json ToJson(const TripletStats& stats);

}  // namespace pgba
