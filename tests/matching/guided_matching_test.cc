// Guided matching against a synthetic truth: a scene where every true feature of image 2 has
// a look-alike elsewhere in the image (repetitive, weakly textured surfaces), so the ratio
// test over the whole image rejects almost every true match; within the epipolar band of
// the true geometry the look-alikes are gone. Then VerifyPair: a weak pair with 30 putative
// matches is rejected without guided matching and verified with it, its rotation close to
// the truth.
#include "matching/guided_matching.h"

#include <gtest/gtest.h>

#include <iostream>
#include <random>

#include "matching/two_view_verification.h"
#include "pgba/geometry/rotation.h"
#include "pgba/scene/camera.h"

namespace pgba {
namespace {

constexpr double kFocal = 800.0;

Camera MakeCamera() {
  Camera c;
  c.model = CameraModel::kPinhole;
  c.width = 640;
  c.height = 480;
  c.params = {kFocal, kFocal, 320, 240};
  return c;
}

struct Scene {
  Eigen::Matrix3d R_21;
  Eigen::Vector3d t_21;
  FeatureSet f1, f2;
  int num_true = 0;  // feature k of image 1 is feature k of image 2 for k < num_true
};

void PushDescriptor(const std::vector<int>& d, std::mt19937_64& rng, double noise, cv::Mat* m) {
  std::normal_distribution<double> n(0.0, noise);
  cv::Mat row(1, kSiftDescriptorSize, CV_8U);
  for (int k = 0; k < kSiftDescriptorSize; ++k)
    row.at<uint8_t>(0, k) = static_cast<uint8_t>(std::clamp(d[k] + n(rng), 0.0, 255.0));
  m->push_back(row);
}

// `n` points seen by both cameras (0.5 px noise); image 2 also holds one look-alike per
// point (its descriptor with the same noise as the true match) at a random pixel.
Scene MakeScene(uint64_t seed, int n) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0), depth(4.0, 6.0), byte(0.0, 60.0);
  std::normal_distribution<double> px(0.0, 0.5);
  const Camera cam = MakeCamera();
  Scene s;
  const Eigen::Vector3d C2(0.8, 0.1, 0.2);
  const Eigen::Matrix3d R2 = RandomRotationOfAngle(rng, 8.0 * M_PI / 180.0);
  s.R_21 = R2;
  s.t_21 = (-R2 * C2).normalized();
  s.f1.width = s.f2.width = cam.width;
  s.f1.height = s.f2.height = cam.height;
  std::vector<std::vector<int>> descriptors;
  while (s.num_true < n) {
    const Eigen::Vector3d X(u(rng) * 1.5, u(rng) * 1.1, depth(rng));
    const Eigen::Vector3d x2 = R2 * (X - C2);
    const Eigen::Vector2d p1 = cam.Project(X), p2 = cam.Project(x2);
    if (p1.x() < 0 || p1.y() < 0 || p1.x() > cam.width || p1.y() > cam.height) continue;
    if (x2.z() < 0.5 || p2.x() < 0 || p2.y() < 0 || p2.x() > cam.width || p2.y() > cam.height) continue;
    std::vector<int> d(kSiftDescriptorSize);
    for (int& v : d) v = static_cast<int>(byte(rng));
    descriptors.push_back(d);
    s.f1.keypoints.push_back({static_cast<float>(p1.x() + px(rng)), static_cast<float>(p1.y() + px(rng)), 2.f, 0.f});
    s.f2.keypoints.push_back({static_cast<float>(p2.x() + px(rng)), static_cast<float>(p2.y() + px(rng)), 2.f, 0.f});
    PushDescriptor(d, rng, 3.0, &s.f1.descriptors);
    PushDescriptor(d, rng, 3.0, &s.f2.descriptors);
    ++s.num_true;
  }
  for (int k = 0; k < n; ++k) {
    s.f2.keypoints.push_back({static_cast<float>((u(rng) + 1) * 320), static_cast<float>((u(rng) + 1) * 240), 2.f, 0.f});
    PushDescriptor(descriptors[k], rng, 3.0, &s.f2.descriptors);
  }
  return s;
}

std::vector<Eigen::Vector3d> Bearings(const FeatureSet& f) {
  const Camera cam = MakeCamera();
  std::vector<Eigen::Vector3d> b;
  for (const Keypoint& k : f.keypoints) b.push_back(cam.PixelToBearing(Eigen::Vector2d(k.x, k.y)));
  return b;
}

float Distance(const cv::Mat& a, int i, const cv::Mat& b, int j) {
  return static_cast<float>(cv::norm(a.row(i), b.row(j), cv::NORM_L2));
}

TEST(GuidedMatching, RecoversTheMatchesTheWholeImageRatioTestRejects) {
  const Scene s = MakeScene(7, 300);
  GuidedMatchingOptions o;
  // The ratio test over the whole image (exact nearest neighbours) keeps few true matches:
  // the look-alike is about as close as the true partner.
  int global_true = 0;
  for (int i = 0; i < s.num_true; ++i) {
    float best = 1e9f, second = 1e9f;
    int arg = -1;
    for (int j = 0; j < s.f2.descriptors.rows; ++j) {
      const float d = Distance(s.f1.descriptors, i, s.f2.descriptors, j);
      if (d < best) second = best, best = d, arg = j;
      else if (d < second) second = d;
    }
    if (arg == i && best < 0.8f * second) ++global_true;
  }
  EXPECT_LT(global_true, s.num_true / 5);

  const auto matches = GuidedMatches(s.R_21, s.t_21, Bearings(s.f1), s.f1.descriptors, Bearings(s.f2),
                                     s.f2.descriptors, kFocal, 2.0, o);
  int correct = 0;
  for (const auto& [i, j] : matches) correct += (i == j);
  // A look-alike falls in the 2 px band of its point with probability ~ 4 px * 700 px /
  // (640 * 480) ~ 1%, and then usually loses the ratio test: nearly all true matches come
  // back and nearly none are wrong.
  EXPECT_GE(correct, s.num_true * 95 / 100) << matches.size() << " matches";
  EXPECT_LE(static_cast<int>(matches.size()) - correct, s.num_true / 100);
}

TEST(GuidedMatching, VerifiesAWeakPairThePutativeMatchesAloneCannot) {
  const Scene s = MakeScene(11, 300);
  // The descriptor test kept 30 true matches (as on a weakly textured pair).
  std::vector<std::pair<uint32_t, uint32_t>> putative;
  for (uint32_t k = 0; k < 30; ++k) putative.emplace_back(k * 10, k * 10);
  const Camera cam = MakeCamera();
  VerificationOptions o;
  PairCheck without, with;
  EXPECT_FALSE(VerifyPair(1, cam, s.f1, 2, cam, s.f2, putative, o, 1.0, &without));
  EXPECT_EQ(without.verdict, "few_matches");
  EXPECT_EQ(without.guided, 0);

  o.guided.enabled = true;
  const auto verified = VerifyPair(1, cam, s.f1, 2, cam, s.f2, putative, o, 1.0, &with);
  ASSERT_TRUE(verified) << with.verdict;
  EXPECT_EQ(with.verdict, "verified");
  EXPECT_GE(with.guided, 250);
  EXPECT_GE(with.inliers, 270);
  int correct = 0;
  for (const auto& [i, j] : verified->inlier_matches) correct += (i == j);
  EXPECT_GE(correct, static_cast<int>(verified->inlier_matches.size()) - 3);
  // Against the 30 putative matches alone (accepted here by lowering min_inliers): the
  // rotation is closer to the truth and ~sqrt(9) times more certain.
  VerificationOptions few;
  few.relative_pose.min_inliers = 15;
  PairCheck alone;
  const auto thirty = VerifyPair(1, cam, s.f1, 2, cam, s.f2, putative, few, 1.0, &alone);
  ASSERT_TRUE(thirty) << alone.verdict;
  const double error_with = RotationAngleDeg(verified->geometry.R_21, s.R_21);
  const double error_alone = RotationAngleDeg(thirty->geometry.R_21, s.R_21);
  std::cout << "rotation error: guided " << error_with << " deg (sd " << with.rotation_sd_deg << "), 30 matches "
            << error_alone << " deg (sd " << alone.rotation_sd_deg << ")" << std::endl;
  EXPECT_LT(error_with, 2 * with.rotation_sd_deg);
  EXPECT_LT(with.rotation_sd_deg, alone.rotation_sd_deg / 2);
  EXPECT_LT(error_with, error_alone);
}

}  // namespace
}  // namespace pgba
