// Geometric verification of one image pair: the putative matches become undistorted unit
// bearings (Camera::PixelToBearing), the calibrated relative pose is estimated by OpenGV's
// 5-point RANSAC + refinement (relative_pose.h, EstimateRelativePose), and the matches
// consistent with it are kept with the two-view geometry for the triplet stage.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <utility>
#include <vector>

#include "features/feature_set.h"
#include "matching/relative_pose.h"
#include "pgba/scene/camera.h"
#include "pgba/scene/view_graph.h"

namespace pgba {

// The relative-pose defaults of verification: threshold 1 px (in pixels of the images SIFT
// ran on, see VerifyPair) and at least 30 inliers. Measured on temple_sparse_ring
// (640x480, f = 1520 px, i.e. a 24 degree field of view where rotation and translation are
// hard to separate): 2 px gave a median rotation error of 1.2 deg, 1 px 0.55-0.85 deg; the
// pairs with gross errors (> 5 deg) all had fewer than 30 inliers.
inline RelativePoseOptions DefaultVerificationPoseOptions() {
  RelativePoseOptions o;
  o.threshold_px = 1.0;
  o.min_inliers = 30;
  return o;
}

struct VerificationOptions {
  // RANSAC threshold, minimal solver, iterations, minimum inlier count and refinement. The
  // seed is mixed with the pair's image ids so that every pair has its own reproducible
  // sampling whatever order the pairs run in.
  RelativePoseOptions relative_pose = DefaultVerificationPoseOptions();
  // Pairs whose inliers are fewer than this fraction of the putative matches are rejected:
  // a handful of consistent matches among hundreds of random ones is how repetitive texture
  // or a watermark fools RANSAC.
  double min_inlier_ratio = 0.1;
};
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(VerificationOptions, relative_pose, min_inlier_ratio)

struct VerifiedPair {
  TwoViewGeometry geometry;  // num_tracks is filled later, once tracks exist
  std::vector<std::pair<uint32_t, uint32_t>> inlier_matches;
};

// nullopt if the pair fails (too few matches or inliers, RANSAC failure). Keypoints are in
// full-resolution pixels; `detection_scale` (full-resolution pixels per pixel of the image
// SIFT ran on, the larger of the two images') scales the pixel threshold, since keypoint
// noise is a fraction of a detection pixel.
std::optional<VerifiedPair> VerifyPair(uint32_t image_id1, const Camera& camera1,
                                       const std::vector<Keypoint>& keypoints1, uint32_t image_id2,
                                       const Camera& camera2, const std::vector<Keypoint>& keypoints2,
                                       const std::vector<std::pair<uint32_t, uint32_t>>& matches,
                                       const VerificationOptions& options, double detection_scale = 1.0);

}  // namespace pgba
