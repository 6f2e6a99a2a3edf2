#include "mapper/image_registration.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "pgba/geometry/rotation.h"

namespace pgba {
namespace {

double Median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  const size_t mid = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + mid, v.end());
  return v[mid];
}

std::string Fixed(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), format, v);
  return buf;
}

}  // namespace

nlohmann::json AbsoluteRegistration::ToJson() const {
  nlohmann::json j = {{"correspondences", correspondences},
                      {"inliers", inliers},
                      {"median_error_px", median_error_px},
                      {"pairs", pairs},
                      {"pair_rotation_median_deg", pair_rotation_median_deg}};
  if (!failure.empty()) j["failure"] = failure;
  return j;
}

AbsoluteRegistration RegisterByAbsolutePose(const Reconstruction& tracks, const Reconstruction& model,
                                            const std::vector<TwoViewGeometry>& pairs, uint32_t image_id,
                                            const ImageRegistrationOptions& options) {
  AbsoluteRegistration r;
  r.image_id = image_id;
  const Image& image = tracks.images.at(image_id);
  const Camera& camera = tracks.CameraOf(image);
  std::vector<Eigen::Vector3d> bearings, points;
  std::vector<Eigen::Vector2d> pixels;
  for (const Point2D& p : image.points2D) {
    if (p.point3D_id == kNoPoint3D) continue;
    const auto it = model.points3D.find(static_cast<uint64_t>(p.point3D_id));
    if (it == model.points3D.end()) continue;
    bearings.push_back(camera.PixelToBearing(p.xy).normalized());
    points.push_back(it->second.xyz);
    pixels.push_back(p.xy);
  }
  r.correspondences = static_cast<int>(points.size());
  if (r.correspondences < options.min_correspondences) {
    r.failure = std::to_string(r.correspondences) + " observations of the model's points (fewer than " +
                std::to_string(options.min_correspondences) + ")";
    return r;
  }
  const AbsolutePoseResult pose = EstimateAbsolutePose(bearings, points, camera.MeanFocal(), options.absolute_pose);
  if (!pose.success) {
    r.failure = "no absolute pose (" + std::to_string(pose.num_inliers) + " inliers of " +
                std::to_string(r.correspondences) + ")";
    return r;
  }
  r.estimated = true;
  r.pose = pose.pose;
  r.inliers = pose.num_inliers;
  std::vector<double> errors;
  for (size_t i = 0; i < points.size(); ++i)
    if (pose.inlier_mask[i]) errors.push_back((camera.Project(r.pose.ToCamera(points[i])) - pixels[i]).norm());
  r.median_error_px = Median(errors);
  // The two-view rotations of the image's verified pairs with the model's images.
  std::vector<double> disagreement;
  for (const TwoViewGeometry& p : pairs) {
    if (p.image_id1 != image_id && p.image_id2 != image_id) continue;
    const uint32_t other = p.image_id1 == image_id ? p.image_id2 : p.image_id1;
    const auto it = model.images.find(other);
    if (it == model.images.end()) continue;
    const Pose& pose1 = p.image_id1 == image_id ? r.pose : it->second.pose;
    const Pose& pose2 = p.image_id2 == image_id ? r.pose : it->second.pose;
    disagreement.push_back(RotationAngleDeg(p.R_21, pose2.R() * pose1.R().transpose()));
  }
  r.pairs = static_cast<int>(disagreement.size());
  r.pair_rotation_median_deg = Median(disagreement);
  return r;
}

std::string CheckRegistration(const Reconstruction& tracks, const std::vector<TwoViewGeometry>& pairs,
                              const std::map<uint32_t, Pose>& poses, const AbsoluteRegistration& r,
                              const ImageRegistrationOptions& options) {
  if (!r.estimated) return r.failure;
  if (r.inliers < options.min_inlier_ratio * r.correspondences)
    return std::to_string(r.inliers) + " inliers of " + std::to_string(r.correspondences) +
           " correspondences (fewer than " + Fixed("%.0f", 100.0 * options.min_inlier_ratio) + "%)";
  if (r.pairs < options.min_pairs)
    return std::to_string(r.pairs) + " verified pairs with the model's images (fewer than " +
           std::to_string(options.min_pairs) + ")";
  if (r.pair_rotation_median_deg > options.max_pair_rotation_deg)
    return "the pose disagrees with its verified pairs' rotations by " + Fixed("%.2f", r.pair_rotation_median_deg) +
           " deg (median of " + std::to_string(r.pairs) + ", more than " +
           Fixed("%.1f", options.max_pair_rotation_deg) + ")";
  if (options.verification.enabled) {
    const ImageEvidence evidence =
        MeasureImageEvidence(tracks, pairs, poses, r.image_id, r.pose, options.verification);
    if (const std::string failure = VerificationFailure(evidence, options.verification); !failure.empty())
      return "failed verification: " + failure;
  }
  return "";
}

}  // namespace pgba
