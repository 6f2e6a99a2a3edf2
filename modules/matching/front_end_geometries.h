// The image front end's verified two-view geometries as the view graph consumes them
// (triplets/pair_estimation.h, PairOptions::front_end): written by the matching stage to
// WS/matching/two_view_geometries.txt (io/two_view_geometries.h) beside WS/tracks/, read
// back when `pgba run` reuses cached tracks, and checked against those tracks so that a
// stale or edited file fails with its name instead of feeding poses of other images.
#pragma once

#include <string>
#include <vector>

#include "pgba/scene/reconstruction.h"
#include "pgba/scene/view_graph.h"

namespace pgba {

// WS/matching/two_view_geometries.txt.
std::string FrontEndGeometriesPath(const std::string& workspace);

// InputError "ORIGIN: pair (ID1, ID2): problem" for a pair with an image the tracks do not
// have, an image paired with itself, a pair listed twice (in either orientation), a rotation
// that is not one, a zero or non-finite translation or a negative count.
void CheckFrontEndGeometries(const std::vector<TwoViewGeometry>& geometries, const Reconstruction& tracks,
                             const std::string& origin);

// ReadTwoViewGeometries (strict: "FILE:LINE: problem" for a malformed line) then the checks
// above, naming the file.
std::vector<TwoViewGeometry> ReadFrontEndGeometries(const std::string& path, const Reconstruction& tracks);

}  // namespace pgba
