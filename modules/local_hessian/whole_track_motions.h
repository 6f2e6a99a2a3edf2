// Relative motions that hold their tracks whole, each track in exactly one motion.
//
// Why: the point-based BA's reduced camera system is a sum of per-track Schur terms
// (H_cc - H_cp H_pp^-1 H_pc of each point). A motion's local Hessian h_s (paper eq. 3) is the
// sum of the Schur terms of the tracks it triangulates, over its views. So when every track
// lies, with all of its views, in exactly one motion, and every observation has weight 1,
// sum_s h_s (mapped to the global chart) IS the point-based reduced camera system at the
// linearisation point: the pointless global BA (eq. 5) is then the point-based BA's
// Gauss-Newton step with the points eliminated, not an approximation of it. The paper's
// triplets lose against the point-based BA exactly where this fails: a track of L views is
// cut into three-view pieces (each triangulated from three views only, nearly parallel rays
// on a narrow-field ring) and its observations are counted once per triplet that uses them.
//
// How the motions are chosen: one motion per anchor image. Tracks are taken longest first
// (ties by id); each goes to the motion, among those anchored at one of its own views, that
// it enlarges least (fewest views added), as long as the motion stays within max_views; ties
// go to the motion with fewer observations, then to the smallest anchor id. So motions grow
// as windows along the tracks instead of one per image around all its neighbours. A motion
// may exceed max_views only up to the length of its longest track: a track longer than
// max_views that no motion contains opens a motion of its own views. Motions with fewer than min_tracks tracks
// are dissolved and their tracks re-assigned the same way, so that no motion is too weak to
// be modelled (each motion's h must pass the local Hessian stage: a rejected motion would
// lose its tracks).
#pragma once

#include <string>

#include <cstdint>
#include <map>
#include <vector>

#include "pgba/geometry/pose.h"
#include "pgba/scene/reconstruction.h"
#include "pgba/scene/view_graph.h"

namespace pgba {

struct WholeTrackMotionOptions {
  // Largest motion, in views, that a track may grow (a longer track makes its own motion).
  int max_views = 12;
  // Fewest tracks a motion keeps; fewer: its tracks go to other motions.
  int min_tracks = 30;
  // Empty when valid, else one line naming the first field out of its valid range (the
  // ranges of io/option_ranges.cc) or breaking a rule between fields.
  std::string Check() const;
};

// The motions over the images of `poses` (only their observations count: a track with fewer
// than two posed views is left out). Each motion: image ids ascending, local poses = the
// given poses (global frame, global_to_local = identity), track_ids ascending. Every track
// with >= 2 posed views is in exactly one motion, which holds all of its posed views.
// Deterministic (no dependence on thread count or addresses).
std::vector<LocalMotion> SelectWholeTrackMotions(const Reconstruction& tracks, const std::map<uint32_t, Pose>& poses,
                                                 const WholeTrackMotionOptions& options);

}  // namespace pgba
