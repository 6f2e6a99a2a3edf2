// Registration of one image left out of a model's triplets against the model's structure:
// its observations whose tracks the model has triangulated give 2D-3D correspondences, OpenGV's
// P3P inside RANSAC estimates the pose and its nonlinear refinement polishes it on the inliers
// (triplets/absolute_pose.h); the pose is then accepted or rejected by CheckRegistration: at
// least half of the correspondences inliers, the two-view rotations of the image's verified
// pairs agreeing with the registered poses (a pose found on a repeated structure does not),
// and the verification every registered image passes (image_verification.h: its leave-one-out
// reprojections and its pairs).
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "mapper/image_verification.h"
#include "pgba/geometry/pose.h"
#include "pgba/scene/reconstruction.h"
#include "pgba/scene/view_graph.h"
#include "triplets/absolute_pose.h"

namespace pgba {

struct ImageRegistrationOptions {
  AbsolutePoseOptions absolute_pose = [] {
    AbsolutePoseOptions o;
    o.threshold_px = 4.0;
    o.max_iterations = 2000;
    o.min_inliers = 20;
    return o;
  }();
  // An image needs this many 2D-3D correspondences to be tried.
  int min_correspondences = 20;
  // Of the correspondences, at least this fraction must be inliers of the pose.
  double min_inlier_ratio = 0.5;
  // The median angle between the two-view rotation of the image's verified pairs with the
  // model's images and the rotation between the poses (degrees), and how many such pairs
  // must exist.
  double max_pair_rotation_deg = 2.0;
  int min_pairs = 1;
  // The verification of every registered image (PointlessMapperOptions::verification).
  ImageVerificationOptions verification;
};

struct AbsoluteRegistration {
  uint32_t image_id = 0;
  bool estimated = false;  // a pose came out of RANSAC
  Pose pose;               // world -> camera, in the model's frame
  int correspondences = 0;
  int inliers = 0;
  double median_error_px = 0.0;  // over the inliers
  // The image's verified pairs with images of the model, and the median disagreement of
  // their two-view rotations with the poses (degrees; 0 when there is none).
  int pairs = 0;
  double pair_rotation_median_deg = 0.0;
  std::string failure;  // why no pose was estimated

  nlohmann::json ToJson() const;
};

// Image `image_id` of `tracks` against `model` (the tracks triangulated with the model's
// poses: TriangulateModel keeps the track ids, which identify the correspondences);
// `pairs`: the verified pairs of the view graph. Deterministic (options.absolute_pose.seed).
AbsoluteRegistration RegisterByAbsolutePose(const Reconstruction& tracks, const Reconstruction& model,
                                            const std::vector<TwoViewGeometry>& pairs, uint32_t image_id,
                                            const ImageRegistrationOptions& options);

// The acceptance of a registration into the model of `poses` (the image's own entry, if any,
// is not used): empty when accepted, else the reason.
std::string CheckRegistration(const Reconstruction& tracks, const std::vector<TwoViewGeometry>& pairs,
                              const std::map<uint32_t, Pose>& poses, const AbsoluteRegistration& registration,
                              const ImageRegistrationOptions& options);

}  // namespace pgba
