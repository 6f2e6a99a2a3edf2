#include "matching/two_view_verification.h"

namespace pgba {

std::optional<VerifiedPair> VerifyPair(uint32_t image_id1, const Camera& camera1,
                                       const std::vector<Keypoint>& keypoints1, uint32_t image_id2,
                                       const Camera& camera2, const std::vector<Keypoint>& keypoints2,
                                       const std::vector<std::pair<uint32_t, uint32_t>>& matches,
                                       const VerificationOptions& options, double detection_scale) {
  if (static_cast<int>(matches.size()) < std::max(options.relative_pose.min_inliers, 5)) return std::nullopt;
  std::vector<Eigen::Vector3d> b1, b2;
  b1.reserve(matches.size());
  b2.reserve(matches.size());
  for (const auto& [i, j] : matches) {
    b1.push_back(camera1.PixelToBearing(Eigen::Vector2d(keypoints1[i].x, keypoints1[i].y)));
    b2.push_back(camera2.PixelToBearing(Eigen::Vector2d(keypoints2[j].x, keypoints2[j].y)));
  }
  RelativePoseOptions rp = options.relative_pose;
  rp.threshold_px *= std::max(1.0, detection_scale);
  // A per-pair seed (splitmix-style mix of the ids): reproducible, independent of order.
  uint64_t s = rp.seed + 0x9E3779B97F4A7C15ULL * (uint64_t(image_id1) * 2147483647ULL + image_id2);
  s = (s ^ (s >> 30)) * 0xBF58476D1CE4E5B9ULL;
  rp.seed = s ^ (s >> 31);
  const double focal = 0.5 * (camera1.MeanFocal() + camera2.MeanFocal());
  const RelativePoseResult pose = EstimateRelativePose(b1, b2, focal, rp);
  if (!pose.success || pose.num_inliers < rp.min_inliers ||
      pose.num_inliers < options.min_inlier_ratio * static_cast<double>(matches.size()) ||
      !(pose.rotation_sd_deg <= options.max_rotation_sd_deg))
    return std::nullopt;

  VerifiedPair out;
  out.geometry.image_id1 = image_id1;
  out.geometry.image_id2 = image_id2;
  out.geometry.R_21 = pose.R_21;
  out.geometry.t_21 = pose.t_21;
  out.geometry.num_inliers = pose.num_inliers;
  out.geometry.median_triangulation_angle_deg = pose.median_triangulation_angle_deg;
  for (size_t k = 0; k < matches.size(); ++k)
    if (pose.inlier_mask[k]) out.inlier_matches.push_back(matches[k]);
  return out;
}

}  // namespace pgba
