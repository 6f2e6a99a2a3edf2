// The tracks as the triplets see them: for every triplet, a copy of each track restricted to
// the triplet's three views (when it keeps >= 2 of them), as a point of its own. A
// point-based BA over these tracks minimises exactly the sum of the triplets' own bundle
// adjustment costs (paper eq. 1 summed over the triplets, each with its private points),
// which the pointless BA approximates by quadratics (eqs. 3 and 5). Comparing the three
// separates the two things the pointless BA gives up against a point-based BA:
//   pointless vs this:        the local quadratic models (should be ~nothing);
//   this vs full point-based: the triplet structure itself (a point seen by 9 views is
//                             triangulated from 3 at a time).
// Observations shared by several triplets are copied into each (as the local hessians
// count them, LocalHessianOptions::shared_observation_weighting off).
#pragma once

#include <vector>

#include "pgba/scene/reconstruction.h"
#include "pgba/scene/view_graph.h"

namespace pgba {

// Images and cameras as in `tracks`; each image's points2D are its original observations
// (unassigned) followed by one copy per triplet track that uses them.
// The same for relative motions of any N views (local_motions.h): each track restricted to
// each motion's views. SplitTracksByTriplets is the N = 3 case.
Reconstruction SplitTracksByMotions(const Reconstruction& tracks, const std::vector<LocalMotion>& motions);
inline Reconstruction SplitTracksByTriplets(const Reconstruction& tracks, const std::vector<LocalMotion>& triplets) {
  return SplitTracksByMotions(tracks, triplets);
}

}  // namespace pgba
