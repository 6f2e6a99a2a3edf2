// Entry of the triplet stage: from the tracks and the verified pairs (pair_estimation.h) to
// triplets with local poses of one consistent scale, refined by a triplet BA.
//
//   candidates  = triangles of the view graph whose pair rotations close (rotation cycle)
//                 and that share enough tracks; then, only if the estimated triangles leave
//                 the triplet graph in pieces or an image uncovered, open triplets (two
//                 verified pairs a - b - c) that bridge them (TripletOptions::open_triplets);
//   estimation  = triplet_estimation.h, parallel over triplets (TBB, one result slot each);
//   selection   = triplet_selection.h (on by default): candidates are scored before
//                 estimation (tracks seen by all three views x pair angles), the selected
//                 ones estimated, then selection is run again with the estimated ones
//                 locked in and the failures excluded, which adds the next best candidates
//                 where a failure left an image under-covered or the graph disconnected;
//                 until every selected triplet is estimated. Only selected triplets are
//                 ever estimated, which keeps large, highly overlapping sets tractable.
//
// Local frame of every returned LocalMotion (the gauge): image_ids ascending,
// local_poses[0] = identity, |C(local_poses[1]) - C(local_poses[0])| = 1; track_ids are the
// input tracks used by the triplet BA (seen by >= 2 of the 3 views after outlier removal).
#pragma once

#include <vector>

#include "modules/triplets/triplet_options.h"
#include "pgba/scene/reconstruction.h"
#include "pgba/scene/view_graph.h"

namespace pgba {

// Triplets sorted by image_ids. The result does not depend on the number of threads.
// Throws InputError for inconsistent tracks.
std::vector<LocalMotion> BuildTriplets(const Reconstruction& tracks, const std::vector<TwoViewGeometry>& pairs,
                                   const TripletOptions& options, TripletStats* stats = nullptr);

// Triangles of the view graph, each sorted ascending, in lexicographic order.
std::vector<std::array<uint32_t, 3>> EnumerateTriangles(const std::vector<TwoViewGeometry>& pairs);

}  // namespace pgba
