// Where the whole-track motions' local Hessians are taken (pose_refinement.h, default method).
//
// Whole-track motions are linearised at the initial poses, and the pointless global BA is
// then Gauss-Newton on the point-based cost with the points eliminated: two steps (one
// re-linearisation) reach the point-based optimum when the initial poses are close to it.
// They are not on narrow-field blocks: on the synthetic long-focal loops the initial
// rotations are off their triplets by ~1000x the triplets' residual (in pixels), the first
// steps gain a few percent of the cost each and the result ended 40x less accurate than the
// point-based BA. The triplets' pointless BA (the paper's method) does not care where it
// starts: each triplet's model is taken at its own local optimum. Starting the whole-track
// linearisation from its solution costs the triplets' Hessians and one global solve, so it is
// done only when the initial poses are measured to be far.
#pragma once

#include <map>
#include <vector>

#include "pgba/geometry/pose.h"
#include "pgba/scene/reconstruction.h"
#include "pgba/scene/view_graph.h"

namespace pgba {

// How far `initial` is from the triplets' own relative rotations: the median over the
// triplets of max over their three pairs of angle(R_a R_b^T initial vs local) x focal of a,
// in units of the triplet BA's residual RMS (at least 0.1 px). Near-converged starts measure
// 1.7-8 (synthetic orbit, aerial, planar; fountain_p11, herzjesu_p8, entry_p10, also
// uncalibrated), temple_sparse_ring 37-114, the long-focal loops 1065-1192. 0 when no triplet has all three initial poses.
double TripletRotationMisfit(const Reconstruction& tracks, const std::map<uint32_t, Pose>& initial,
                             const std::vector<LocalMotion>& triplets);

// The triplets the start uses: about `max_per_image` per image (most tracks first), covering
// every image and keeping the triplet graph connected (SelectTriplets); all for <= 0.
std::vector<LocalMotion> TripletStartSubset(const std::vector<LocalMotion>& triplets, int max_per_image);

// The poses of the triplets' pointless BA from `initial` (paper settings, one IRLS round of at
// most `max_iterations`, no re-linearisation: only a linearisation point) over
// TripletStartSubset(triplets, max_per_image). Images that BA leaves out keep `initial`.
std::map<uint32_t, Pose> TripletPointlessStart(const Reconstruction& tracks, const std::map<uint32_t, Pose>& initial,
                                               const std::vector<LocalMotion>& triplets, int max_iterations,
                                               int max_per_image);

}  // namespace pgba
