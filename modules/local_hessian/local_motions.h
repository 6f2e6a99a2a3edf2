// Which relative motions the local Hessian stage models (local_motions.kind):
//   whole_tracks  the default: every track lies whole in exactly one motion
//                 (whole_track_motions.h), so that the sum of the local Hessians is the
//                 point-based BA's reduced camera system; h taken at the given poses.
//   triplets      the paper's: the triplets of the initialisation (N = 3).
//   neighbours    one motion of N views per registered image.
// The paper's equations 1-5 hold for motions of any N views, and longer motions keep
// information that triplets lose: a triplet triangulates each point from its three views, so
// the long tracks of a narrow-field sequence (tracks over 10-30 images, where the wide angles
// are) are cut into short, nearly parallel-ray pieces. Measured on the longfocal synthetic
// loops (`pgba benchmark --triplet-split` runs the point-based BA over exactly the pieces a
// motion set sees): the cut pieces, not the quadratic models of the local Hessians, are what
// the pointless BA loses against the point-based BA.
//
// neighbours: one motion per registered image and stride s (neighbour_strides): the image
// with N - 1 of its neighbours ranked by shared tracks, every s-th of them (s = 1: the
// nearest; s = 3: a motion spread three times as far along the tracks). The motion starts
// from given global poses, in their frame; its own local BA converges it
// (ConvergeLocalMotions) before the local Hessian is taken at that solution, as the triplet
// BA does for the triplets. The start must be locally accurate to a few pixels: the
// initialisation is not (tens to hundreds of pixels between neighbours of a long-focal
// sequence), the triplets' pointless BA is (PrepareLocalHessians of pose_refinement.h
// starts the motions there).
#pragma once

#include <string>

#include <map>
#include <nlohmann/json.hpp>
#include <vector>

#include "modules/local_hessian/local_hessian.h"
#include "modules/local_hessian/whole_track_motions.h"
#include "pgba/geometry/pose.h"
#include "pgba/optim/solver_options.h"
#include "pgba/scene/reconstruction.h"
#include "pgba/scene/view_graph.h"
#include "pgba/util/json_fields.h"

namespace pgba {

// Which relative motions model the block.
enum class MotionKind {
  // Each track whole in exactly one motion (whole_track_motions.h): the sum of the local
  // Hessians is the point-based reduced camera system. The default.
  kWholeTracks,
  // The initialisation's triplets (the paper's method; configs/paper_triplets.json).
  kTriplets,
  // One motion of `views` views per image with its best-connected neighbours (above).
  kNeighbours,
};
NLOHMANN_JSON_SERIALIZE_ENUM(MotionKind, {{MotionKind::kWholeTracks, "whole_tracks"},
                                          {MotionKind::kTriplets, "triplets"},
                                          {MotionKind::kNeighbours, "neighbours"}})

struct LocalMotionOptions {
  MotionKind kind = MotionKind::kWholeTracks;
  // kWholeTracks: the largest motion a track may grow, and the fewest tracks of a motion.
  int max_views = 12;
  int min_tracks = 30;
  // kNeighbours: views per motion (> 3).
  int views = 7;
  // A neighbour must share at least this many tracks with the motion's image.
  int min_shared_tracks = 30;
  // The local BA that takes an N-view motion from the initial poses to its own optimum; config
  // key "max_iterations" (solver.max_iterations): its Levenberg-Marquardt iterations (stops
  // earlier on Ceres' tolerances).
  SolverOptions solver = LocalBundleSolverOptions(30);
  // One family of motions per stride s: the image and every s-th of its neighbours ranked by
  // shared tracks (s = 1: the nearest ones; larger s: a motion spread over a longer stretch
  // of the tracks, which catches the long tracks that a window of near neighbours cuts).
  std::vector<int> neighbour_strides = {1};
  // kWholeTracks: when the initial poses are off their triplets' relative rotations by more
  // than this many triplet residuals (median, TripletRotationMisfit of
  // mapper/linearization_start.h), the motions are linearised where the triplets' pointless BA
  // puts the poses instead of at the initial poses. Measured: 1.7-8 on near-converged starts
  // (synthetic orbit, aerial, planar; fountain_p11, herzjesu_p8, entry_p10, also with the
  // focal 10% off or uncalibrated), 37 on temple_sparse_ring (60 uncalibrated, 114 with the
  // focal 10% off: whole tracks from there measured fine, 0.21-0.41 deg), 1065-1192 on the
  // long-focal loops, whose result it takes from 40x to 0.95x the point-based relative
  // rotation error. The threshold sits ~3x from both. <= 0: never.
  double triplet_start_misfit = 300.0;
  // Levenberg-Marquardt iterations of that triplets' pointless BA: it only has to give a
  // linearisation point, which the re-linearisations then move. Long-focal loop seed 1: after
  // 8 iterations the cost sits 0.6% above where 25 (the global BA's cap) leave it, and the
  // result's relative rotation error is the same (0.951x vs 0.954x point-based).
  int triplet_start_max_iterations = 8;
  // The triplets that BA uses: about this many per image, best supported first, plus what
  // keeps their graph connected (triplets/triplet_selection.h); <= 0: every triplet. The
  // start's cost is its triplets' local Hessians (each track again in every triplet that
  // holds it: 84,610 triplet tracks for the 6,768 tracks of a long-focal loop), and a
  // linearisation point needs only a connected, covering subset.
  int triplet_start_max_per_image = 2;
  // Empty when valid, else one line naming the first field out of its valid range (the
  // ranges of io/option_ranges.cc) or breaking a rule between fields.
  std::string Check() const;
};
template <class Visit>
void JsonFields(LocalMotionOptions& o, Visit&& visit) {
  visit("kind", o.kind);
  visit("max_views", o.max_views);
  visit("min_tracks", o.min_tracks);
  visit("views", o.views);
  visit("min_shared_tracks", o.min_shared_tracks);
  visit("max_iterations", o.solver.max_iterations);
  visit("neighbour_strides", o.neighbour_strides);
  visit("triplet_start_misfit", o.triplet_start_misfit);
  visit("triplet_start_max_iterations", o.triplet_start_max_iterations);
  visit("triplet_start_max_per_image", o.triplet_start_max_per_image);
}
PGBA_JSON_FROM_FIELDS(LocalMotionOptions)

// Whether the motions' start must come from the triplets' pointless BA and be converged by
// their own local BA (kNeighbours: local_motions.h above). Whole-track motions need neither:
// their local Hessians are taken at the initial poses and re-linearised by the global BA.
inline bool NeedsConvergedStart(const LocalMotionOptions& options) { return options.kind == MotionKind::kNeighbours; }

// The N-view motions (kNeighbours, options.views > 3) over the images of `poses`, stride by stride:
// image ids (the image first, then its chosen neighbours by decreasing shared tracks, ties by
// id), local poses = the given poses, global_to_local = identity, and track_ids = the tracks
// seen by at least two of the views. Motions with the same set of images are kept once, and
// motions of fewer than 3 views are not made. Deterministic. For views <= 3 the result is
// empty: the triplets serve.
std::vector<LocalMotion> SelectLocalMotions(const Reconstruction& tracks, const std::map<uint32_t, Pose>& poses,
                                            const LocalMotionOptions& options);

// Runs each motion's local BA (paper eq. 1; local_bundle.h with `lh_options`' robust loss and
// gross outlier threshold, gauge held) for up to options.solver.max_iterations and stores the
// solution in local_poses. The poses must start within the threshold of the truth (a view
// whose observations are all dropped as outliers stays where it started). A motion whose problem cannot be built or solved keeps its poses (the local
// Hessian stage then rejects it with its reason). Parallel over motions (TBB).
void ConvergeLocalMotions(const Reconstruction& tracks, const LocalHessianOptions& lh_options,
                          const LocalMotionOptions& options, std::vector<LocalMotion>* motions);

// The motions the local Hessian stage models, before any local BA: by options.kind, the
// whole-track motions over `poses`, the triplets as motions, or SelectLocalMotions over `poses`. Which motions depends only on the
// images of `poses`, so a re-run from a workspace (`reconstruct --workspace`) finds the same
// ones from its initial poses.
std::vector<LocalMotion> ChooseLocalMotions(const Reconstruction& tracks, const std::map<uint32_t, Pose>& poses,
                                            const std::vector<LocalMotion>& triplets, const LocalMotionOptions& options);

// ChooseLocalMotions, the kNeighbours ones then converged from `poses` (ConvergeLocalMotions).
std::vector<LocalMotion> BuildLocalMotions(const Reconstruction& tracks, const std::map<uint32_t, Pose>& poses,
                                           const std::vector<LocalMotion>& triplets,
                                           const LocalHessianOptions& lh_options, const LocalMotionOptions& options);

}  // namespace pgba
