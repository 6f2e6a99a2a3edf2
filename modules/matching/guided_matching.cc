#include "matching/guided_matching.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "pgba/io/option_ranges.h"
#include "matching/relative_pose.h"

namespace pgba {

float SiftDistance(const uint8_t* a, const uint8_t* b) {
  int s = 0;
  for (int k = 0; k < kSiftDescriptorSize; ++k) {
    const int d = int(a[k]) - int(b[k]);
    s += d * d;
  }
  return std::sqrt(static_cast<float>(s));
}

void NearestTwo::Offer(int k, float d) {
  if (d < best) {
    second = best;
    best = d;
    index = k;
  } else if (d < second) {
    second = d;
  }
}

bool NearestTwo::Passes(const GuidedMatchingOptions& options) const {
  return index >= 0 && best <= static_cast<float>(options.max_distance * 512.0) && best < options.max_ratio * second;
}

std::string GuidedMatchingOptions::Check() const {
  if (const std::string m = CheckRanges(*this, "matching.verification.guided"); !m.empty()) return m;
  if (min_inliers > max_inliers) return "min_inliers: must not exceed max_inliers";
  return "";
}

std::vector<std::pair<uint32_t, uint32_t>> GuidedMatches(const Eigen::Matrix3d& R_21, const Eigen::Vector3d& t_21,
                                                         const std::vector<Eigen::Vector3d>& bearings1,
                                                         const cv::Mat& descriptors1,
                                                         const std::vector<Eigen::Vector3d>& bearings2,
                                                         const cv::Mat& descriptors2, double focal_px,
                                                         double threshold_px, const GuidedMatchingOptions& options) {
  const double angle = std::atan(threshold_px / focal_px);
  const int n1 = static_cast<int>(bearings1.size()), n2 = static_cast<int>(bearings2.size());
  // Forward: best of each i over the band; backward: best of each j. A pair is kept when
  // each is the other's best and the forward best passes the ratio test.
  std::vector<NearestTwo> forward(n1), backward(n2);
  for (int i = 0; i < n1; ++i) {
    const uint8_t* d1 = descriptors1.ptr<uint8_t>(i);
    for (int j = 0; j < n2; ++j) {
      if (!(std::abs(SampsonAngle(R_21, t_21, bearings1[i], bearings2[j])) < angle)) continue;
      if (!InFrontOfBoth(R_21, t_21, bearings1[i], bearings2[j], angle)) continue;
      const float d = SiftDistance(d1, descriptors2.ptr<uint8_t>(j));
      forward[i].Offer(j, d);
      backward[j].Offer(i, d);
    }
  }
  std::vector<std::pair<uint32_t, uint32_t>> matches;
  for (int i = 0; i < n1; ++i) {
    const NearestTwo& f = forward[i];
    if (!f.Passes(options) || backward[f.index].index != i) continue;
    matches.emplace_back(static_cast<uint32_t>(i), static_cast<uint32_t>(f.index));
  }
  return matches;
}

}  // namespace pgba
