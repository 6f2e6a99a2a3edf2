// Guided matching with triplets: transfer into the third view. For every triangle (i, j, k)
// of kept pairs whose baselines close (FrameOfTriangle), a match a <-> b of pair (i, j)
// whose features have no partner in k is triangulated in the triangle's frame and projected
// into k; the features of k within `threshold_px` of the projection are the candidates, and
// the one whose descriptor is nearest a's (ratio test among the candidates, absolute bound)
// becomes the partner of a in (i, k) and of b in (j, k). Each of the triangle's three pairs
// transfers into its third view. The matches added make two-view matches three-view
// tracks, which the triplet stage counts (TripletOptions::min_tracks) and measures scale on.
#pragma once

#include <Eigen/Core>
#include <map>
#include <opencv2/core.hpp>
#include <vector>

#include "matching/guided_matching.h"
#include "matching/triplet_confirmation.h"

namespace pgba {

// One image's features as the transfer sees them: unit bearings (camera frame) and the
// descriptors (row k is feature k's).
struct TransferView {
  const std::vector<Eigen::Vector3d>* bearings = nullptr;
  const cv::Mat* descriptors = nullptr;
};

// Adds the transferred matches to `pairs` (each keeps its orientation; matches re-sorted)
// and returns how many each pair gained. `views` holds every image of `pairs`. Uses
// options.threshold_px (converted to an angle by focal_px), max_ratio and max_distance.
// Deterministic: triangles in image order, each pair's matches in their order.
std::vector<int> TransferIntoThirdViews(std::vector<PairEstimate>* pairs, const std::map<uint32_t, TransferView>& views,
                                        double focal_px, const GuidedMatchingOptions& options);

}  // namespace pgba
