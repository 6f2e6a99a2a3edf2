// Geometric verification of one image pair: the putative matches become undistorted unit
// bearings (Camera::PixelToBearing), the calibrated relative pose is estimated by OpenGV's
// 5-point RANSAC + refinement (relative_pose.h, EstimateRelativePose), and the matches
// consistent with it are kept with the two-view geometry for the triplet stage.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "features/feature_set.h"
#include "matching/guided_matching.h"
#include "matching/relative_pose.h"
#include "matching/triplet_confirmation.h"
#include "pgba/scene/camera.h"
#include "pgba/scene/view_graph.h"

namespace pgba {

// The relative-pose defaults of verification: threshold 1 px (in pixels of the images SIFT
// ran on, see VerifyPair) and at least 40 inliers. Measured on temple_sparse_ring
// (640x480, f = 1520 px, i.e. a 24 degree field of view where rotation and translation are
// hard to separate): 2 px gave a median rotation error of 1.2 deg, 1 px 0.55-0.85 deg; the
// pairs with gross errors (> 5 deg) all had fewer than 30 inliers. On the rendered room
// (pgba synth --render, 20 views), 5 of the 6 pairs with errors above 5 degrees had 31-39
// inliers, all on a small patch at the border of both images; temple lost one pair (34
// inliers, 2 deg) to the step from 30 to 40.
inline RelativePoseOptions DefaultVerificationPoseOptions() {
  RelativePoseOptions o;
  o.threshold_px = 1.0;
  o.min_inliers = 40;
  // Sampson-scored RANSAC (essential_ransac.h): on fountain_p11 the same verified pairs and
  // inliers (66,928 vs 66,937) for 0.45x of the verification time.
  o.scoring = "sampson";
  o.refine_passes = 6;
  o.refine_until_converged = true;
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
  // Pairs whose rotation is this uncertain (RelativePoseResult::rotation_sd_deg, degrees)
  // are rejected: their relative rotation would mislead rotation averaging and the triplet
  // stage. Measured: actual errors are 1-5 x this value, up to 20 x for pairs whose matches
  // cover a small planar patch. With min_inliers 40, 1 degree takes the rendered room from
  // 96 to 84 pairs (errors above 5 degrees: 6 -> 1, max 22 -> 5.6 deg, median 0.108 ->
  // 0.087), temple_sparse_ring from 24 to 22 (median 0.395 -> 0.377 deg) and fountain_p11
  // from 50 to 49 (0.045 -> 0.043 deg).
  double max_rotation_sd_deg = 1.0;
  // Weak pairs (guided_matching.h): more matches along the first estimate's epipolar
  // geometry, then the relative pose once more on them; the checks above apply to the result.
  GuidedMatchingOptions guided;
  // Weak pairs (triplet_confirmation.h): a pair failing only the inlier count or the
  // rotation bound above, within the looser bounds there, is kept when a third view
  // confirms it once every pair is verified (MatchImages).
  TripletConfirmationOptions weak_pairs;
  // Empty when valid, else one line naming the first field out of its valid range (the
  // ranges of io/option_ranges.cc) or breaking a rule between fields.
  std::string Check() const;
};
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(VerificationOptions, relative_pose, min_inlier_ratio,
                                                max_rotation_sd_deg, guided, weak_pairs)

// What verification found for one pair, verified or not: the per-pair table of the matching
// stage (WS/matching/pairs.txt) that says where a weak image lost its pairs.
struct PairCheck {
  int putative = 0;
  int guided = 0;   // matches guided matching added to the putative inliers (0 when not run)
  int inliers = 0;  // of the final RANSAC + refinement (0 when RANSAC did not run or failed)
  double rotation_sd_deg = 0.0;
  double median_triangulation_angle_deg = 0.0;
  // verified | few_matches | ransac_failed | few_inliers | low_inlier_ratio | uncertain_rotation,
  // or, with weak_pairs enabled, weak (returned by VerifyPair), which MatchImages turns into
  // confirmed or leaf (kept) or unconfirmed.
  std::string verdict;
};

struct VerifiedPair {
  TwoViewGeometry geometry;  // num_tracks is filled later, once tracks exist
  std::vector<std::pair<uint32_t, uint32_t>> inlier_matches;
};

// Undistorted unit bearings of keypoints (Camera::PixelToBearing), in their order.
std::vector<Eigen::Vector3d> KeypointBearings(const Camera& camera, const std::vector<Keypoint>& keypoints);

// nullopt if the pair fails (too few matches or inliers, RANSAC failure); a weak pair
// (options.weak_pairs) is returned with the verdict "weak". Keypoints are in
// full-resolution pixels (descriptors are read by guided matching only); `detection_scale` (full-resolution pixels per pixel of the image
// SIFT ran on, the larger of the two images') scales the pixel threshold, since keypoint
// noise is a fraction of a detection pixel.
std::optional<VerifiedPair> VerifyPair(uint32_t image_id1, const Camera& camera1, const FeatureSet& features1,
                                       uint32_t image_id2, const Camera& camera2, const FeatureSet& features2,
                                       const std::vector<std::pair<uint32_t, uint32_t>>& matches,
                                       const VerificationOptions& options, double detection_scale = 1.0,
                                       PairCheck* check = nullptr);

}  // namespace pgba
