#include "matching/two_view_verification.h"
#include "pgba/io/option_ranges.h"

#include <algorithm>

namespace pgba {
namespace {

// The correspondences' bearings, in the order of `matches`.
void MatchBearings(const std::vector<Eigen::Vector3d>& all1, const std::vector<Eigen::Vector3d>& all2,
                   const std::vector<std::pair<uint32_t, uint32_t>>& matches, std::vector<Eigen::Vector3d>* b1,
                   std::vector<Eigen::Vector3d>* b2) {
  b1->clear();
  b2->clear();
  for (const auto& [i, j] : matches) {
    b1->push_back(all1[i]);
    b2->push_back(all2[j]);
  }
}

}  // namespace

std::vector<Eigen::Vector3d> KeypointBearings(const Camera& camera, const std::vector<Keypoint>& keypoints) {
  std::vector<Eigen::Vector3d> b;
  b.reserve(keypoints.size());
  for (const Keypoint& k : keypoints) b.push_back(camera.PixelToBearing(Eigen::Vector2d(k.x, k.y)));
  return b;
}

std::optional<VerifiedPair> VerifyPair(uint32_t image_id1, const Camera& camera1, const FeatureSet& features1,
                                       uint32_t image_id2, const Camera& camera2, const FeatureSet& features2,
                                       const std::vector<std::pair<uint32_t, uint32_t>>& matches,
                                       const VerificationOptions& options, double detection_scale,
                                       PairCheck* check) {
  PairCheck local;
  PairCheck& c = check ? *check : local;
  c = PairCheck();
  c.putative = static_cast<int>(matches.size());
  const auto reject = [&c](const char* verdict) {
    c.verdict = verdict;
    return std::nullopt;
  };
  const GuidedMatchingOptions& guided = options.guided;
  const TripletConfirmationOptions& weak = options.weak_pairs;
  // The fewest inliers anything below may use: the guide's, or a weak pair's.
  int fewest = options.relative_pose.min_inliers;
  if (guided.enabled) fewest = std::min(fewest, guided.min_inliers);
  if (weak.enabled) fewest = std::min(fewest, weak.min_inliers);
  const int min_matches = std::max(fewest, 5);
  if (static_cast<int>(matches.size()) < min_matches) return reject("few_matches");
  const std::vector<Eigen::Vector3d> all1 = KeypointBearings(camera1, features1.keypoints);
  const std::vector<Eigen::Vector3d> all2 = KeypointBearings(camera2, features2.keypoints);
  std::vector<Eigen::Vector3d> b1, b2;
  MatchBearings(all1, all2, matches, &b1, &b2);
  RelativePoseOptions rp = options.relative_pose;
  rp.threshold_px *= std::max(1.0, detection_scale);
  // A per-pair seed (splitmix-style mix of the ids): reproducible, independent of order.
  uint64_t s = rp.seed + 0x9E3779B97F4A7C15ULL * (uint64_t(image_id1) * 2147483647ULL + image_id2);
  s = (s ^ (s >> 30)) * 0xBF58476D1CE4E5B9ULL;
  rp.seed = s ^ (s >> 31);
  const double focal = 0.5 * (camera1.MeanFocal() + camera2.MeanFocal());
  // The guide and a weak pair may have fewer inliers than a verified pair needs: that is
  // what they are for.
  RelativePoseOptions first = rp;
  first.min_inliers = fewest;
  RelativePoseResult pose = EstimateRelativePose(b1, b2, focal, first);
  if (pose.num_inliers == 0) {
    c.verdict = "ransac_failed";
    return std::nullopt;
  }
  // The inlier ratio is the descriptor test's own evidence: checked before guided matching
  // adds matches that agree with the geometry by construction.
  if (pose.num_inliers < options.min_inlier_ratio * static_cast<double>(matches.size())) {
    c.inliers = pose.num_inliers;
    c.rotation_sd_deg = pose.rotation_sd_deg;
    return reject("low_inlier_ratio");
  }

  std::vector<std::pair<uint32_t, uint32_t>> used = matches;
  if (guided.enabled && pose.num_inliers >= guided.min_inliers && pose.num_inliers < guided.max_inliers) {
    // The putative inliers plus the guided matches (a feature keeps its putative partner).
    std::vector<std::pair<uint32_t, uint32_t>> merged;
    std::vector<uint8_t> taken1(features1.size(), 0), taken2(features2.size(), 0);
    for (size_t k = 0; k < matches.size(); ++k)
      if (pose.inlier_mask[k]) {
        merged.push_back(matches[k]);
        taken1[matches[k].first] = taken2[matches[k].second] = 1;
      }
    for (const auto& m : GuidedMatches(pose.R_21, pose.t_21, all1, features1.descriptors, all2,
                                       features2.descriptors, focal,
                                       guided.threshold_px * std::max(1.0, detection_scale), guided))
      if (!taken1[m.first] && !taken2[m.second]) {
        merged.push_back(m);
        ++c.guided;
      }
    std::sort(merged.begin(), merged.end());
    MatchBearings(all1, all2, merged, &b1, &b2);
    RelativePoseResult again = EstimateRelativePose(b1, b2, focal, rp);
    if (again.num_inliers > pose.num_inliers) {
      pose = std::move(again);
      used = std::move(merged);
    }
  }

  c.inliers = pose.num_inliers;
  c.rotation_sd_deg = pose.rotation_sd_deg;
  c.median_triangulation_angle_deg = pose.median_triangulation_angle_deg;
  const bool few = pose.num_inliers < rp.min_inliers;
  const bool uncertain = !(pose.rotation_sd_deg <= options.max_rotation_sd_deg);
  if (few || uncertain) {
    if (!weak.enabled || pose.num_inliers < weak.min_inliers || !(pose.rotation_sd_deg <= weak.max_rotation_sd_deg))
      return reject(few ? "few_inliers" : "uncertain_rotation");
    c.verdict = "weak";
  } else {
    c.verdict = "verified";
  }

  VerifiedPair out;
  out.geometry.image_id1 = image_id1;
  out.geometry.image_id2 = image_id2;
  out.geometry.R_21 = pose.R_21;
  out.geometry.t_21 = pose.t_21;
  out.geometry.num_inliers = pose.num_inliers;
  out.geometry.median_triangulation_angle_deg = pose.median_triangulation_angle_deg;
  for (size_t k = 0; k < used.size(); ++k)
    if (pose.inlier_mask[k]) out.inlier_matches.push_back(used[k]);
  return out;
}

std::string VerificationOptions::Check() const {
  if (const std::string m = CheckRanges(*this, "matching.verification"); !m.empty()) return m;
  return "";
}

}  // namespace pgba
