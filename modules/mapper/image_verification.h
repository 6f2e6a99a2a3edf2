// Verification of every registered image after the final adjustment (PointlessMapper step 8):
// no image leaves pgba placed wrong without a word. An image is verified by two independent
// kinds of evidence:
//  - its own observations: each track it sees with at least two other registered views is
//    triangulated from those other views alone (the image left out, so a wrong pose cannot
//    pull the points towards itself), and the image's observation of it reprojected with the
//    image's pose: an inlier within `inlier_px`. A correctly placed image sees most of them as
//    inliers (noise and a few false matches aside); an image a degree or more off sees almost
//    none (1 deg is 15 px at a focal of 900 px).
//  - its verified image pairs: the relative rotation its pose makes with each registered
//    partner against the pair's two-view rotation (the essential matrix of the front end's or
//    the pipeline's verification, which knows nothing of the global solution).
// An image that fails is registered again from the structure: absolute pose (P3P in RANSAC,
// then a nonlinear refinement on the inliers) on those same leave-one-out points, and the new
// pose verified by the same criteria; if it fails again, the image is dropped. Each image's
// verdict, with the numbers it rests on and the reason for a failure, goes to report.json.
#pragma once

#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "pgba/geometry/pose.h"
#include "pgba/scene/reconstruction.h"
#include "pgba/scene/view_graph.h"
#include "pgba/util/json_fields.h"
#include "triplets/absolute_pose.h"

namespace pgba {

struct ImageVerificationOptions {
  // Verify every registered image after the final adjustment (false: the step is skipped).
  bool enabled = true;
  // An observation is an inlier when its reprojection error is below this (pixels): the
  // local Hessians' and the point-based BA's outlier threshold.
  double inlier_px = 4.0;
  // Leave-one-out points whose other views meet at less than this (degrees) are not used:
  // their depth, and so the reprojection into the image, is not determined.
  double min_triangulation_angle_deg = 1.0;
  // The observation test needs at least this many leave-one-out points; with fewer the image
  // is judged by its pairs alone (and an image with neither is reported as unverifiable).
  int min_checked_observations = 12;
  // Fail: fewer than this fraction of the checked observations are inliers.
  double min_inlier_ratio = 0.5;
  // Fail: the median over the image's verified pairs of the angle between the relative
  // rotation of the poses and the pair's two-view rotation exceeds this (degrees).
  double max_pair_rotation_deg = 5.0;
  // A failing image is registered again from the structure (else dropped at once).
  bool reregister = true;
  // Empty when valid, else one line naming the first field out of its valid range (the
  // ranges of io/option_ranges.cc) or breaking a rule between fields.
  std::string Check() const;
};
template <class Visit>
void JsonFields(ImageVerificationOptions& o, Visit&& visit) {
  visit("enabled", o.enabled);
  visit("inlier_px", o.inlier_px);
  visit("min_triangulation_angle_deg", o.min_triangulation_angle_deg);
  visit("min_checked_observations", o.min_checked_observations);
  visit("min_inlier_ratio", o.min_inlier_ratio);
  visit("max_pair_rotation_deg", o.max_pair_rotation_deg);
  visit("reregister", o.reregister);
}
PGBA_JSON_FROM_FIELDS(ImageVerificationOptions)

// The evidence on one image at one pose.
struct ImageEvidence {
  int observations_checked = 0;  // observations with a leave-one-out point
  int inliers = 0;
  int pairs_checked = 0;              // verified pairs with both images registered
  double pair_rotation_deg = 0.0;     // median rotation disagreement over them (0: none)
  double inlier_ratio() const { return observations_checked ? double(inliers) / observations_checked : 0.0; }
};

enum class ImageVerdictStatus { kVerified, kReregistered, kDropped };

struct ImageVerdict {
  uint32_t image_id = 0;
  ImageVerdictStatus status = ImageVerdictStatus::kVerified;
  ImageEvidence evidence;       // at the adjusted pose
  ImageEvidence reregistered;   // at the pose registered again (kReregistered / kDropped after a try)
  // Why the adjusted pose failed (empty when verified), and for a dropped image why the
  // registration again did not succeed.
  std::string reason;
  double moved_deg = 0.0;  // kReregistered: rotation between the adjusted and the new pose
};

struct ImageVerificationResult {
  std::map<uint32_t, Pose> poses;  // the verified and re-registered images' poses
  std::vector<ImageVerdict> verdicts;  // one per input pose, by image id
  int num_reregistered = 0;
  int num_dropped = 0;
  // report.json: counts and one record per image that was not verified at once.
  nlohmann::json ToJson(const Reconstruction& tracks) const;
};

// The evidence on image `image_id` at `pose`, the other images at `poses` (the image's own
// entry in `poses`, if any, is not used).
ImageEvidence MeasureImageEvidence(const Reconstruction& tracks, const std::vector<TwoViewGeometry>& pairs,
                                   const std::map<uint32_t, Pose>& poses, uint32_t image_id, const Pose& pose,
                                   const ImageVerificationOptions& options);

// Empty when `evidence` passes the criteria, else the reason in a user's words.
std::string VerificationFailure(const ImageEvidence& evidence, const ImageVerificationOptions& options);

// After a second verification of a model adjusted again: the first one's verdicts on the images
// it did not verify at once (dropped, or registered again) in place of the second's on the same
// images (or added, for an image the second did not see), counts updated: a record of what
// happened to each image.
void KeepFirstVerdicts(const ImageVerificationResult& first, ImageVerificationResult* second);

// Every image of `poses` verified; the failing ones registered again or dropped (above).
// Deterministic for any thread count.
ImageVerificationResult VerifyRegisteredImages(const Reconstruction& tracks, const std::vector<TwoViewGeometry>& pairs,
                                               const std::map<uint32_t, Pose>& poses,
                                               const ImageVerificationOptions& options);

}  // namespace pgba
