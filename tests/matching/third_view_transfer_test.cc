// Transfer into the third view against a synthetic truth: three cameras on a ring (23.5
// degrees apart, a 20 degree field of view) seeing 200 points on a small object; feature f
// of every image is point f (the same descriptor up to noise), plus 300 distractors per image
// with descriptors of their own. Pair (0, 1) has every match, pairs (0, 2) and (1, 2) only
// the first 40: the transfer gives the other 160 of them their partner in image 2, all
// right, and none to a match whose third-view feature is missing.
#include "matching/third_view_transfer.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

namespace pgba {
namespace {

constexpr double kDeg = M_PI / 180.0;
constexpr double kFocal = 1800.0;
constexpr int kPoints = 200, kDistractors = 300, kShared = 40;

struct View {
  Eigen::Matrix3d R;
  Eigen::Vector3d C;
  std::vector<Eigen::Vector3d> bearings;
  cv::Mat descriptors;
};

Eigen::Matrix3d LookAtOrigin(const Eigen::Vector3d& C) {
  const Eigen::Vector3d z = (-C).normalized(), y(0, 1, 0), x = y.cross(z);
  Eigen::Matrix3d R;
  R.row(0) = x;
  R.row(1) = y;
  R.row(2) = z;
  return R;
}

class ThirdViewTransfer : public ::testing::Test {
 protected:
  void SetUp() override {
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::uniform_int_distribution<int> byte(0, 120);
    std::normal_distribution<double> noise(0.0, 3.0);
    std::vector<Eigen::Vector3d> points;
    std::vector<std::vector<int>> point_descriptor;
    for (int p = 0; p < kPoints; ++p) {
      points.emplace_back(u(rng), u(rng), u(rng));
      std::vector<int> d(kSiftDescriptorSize);
      for (int& v : d) v = byte(rng);
      point_descriptor.push_back(d);
    }
    for (int v = 0; v < 3; ++v) {
      View view;
      const double a = v * 23.5 * kDeg;
      view.C = Eigen::Vector3d(10 * std::sin(a), 0, -10 * std::cos(a));
      view.R = LookAtOrigin(view.C);
      view.descriptors = cv::Mat(kPoints + kDistractors, kSiftDescriptorSize, CV_8U);
      for (int f = 0; f < kPoints + kDistractors; ++f) {
        Eigen::Vector3d b;
        if (f < kPoints) {
          // 0.3 px of noise on the projection.
          b = view.R * (points[f] - view.C);
          b /= b.z();
          b.head<2>() += Eigen::Vector2d(noise(rng), noise(rng)) * (0.1 / kFocal);
        } else {
          b = Eigen::Vector3d(0.1 * u(rng), 0.1 * u(rng), 1.0);
        }
        view.bearings.push_back(b.normalized());
        for (int k = 0; k < kSiftDescriptorSize; ++k) {
          const int value = f < kPoints ? point_descriptor[f][k] + static_cast<int>(noise(rng)) : byte(rng);
          view.descriptors.at<uint8_t>(f, k) = static_cast<uint8_t>(std::clamp(value, 0, 255));
        }
      }
      views_.push_back(view);
    }
    pairs_ = {Pair(0, 1, kPoints), Pair(0, 2, kShared), Pair(1, 2, kShared)};
  }

  PairEstimate Pair(uint32_t a, uint32_t b, int n) const {
    PairEstimate p;
    p.image1 = a;
    p.image2 = b;
    p.R_21 = views_[b].R * views_[a].R.transpose();
    p.t_21 = -views_[b].R * (views_[b].C - views_[a].C);
    for (int f = 0; f < n; ++f) p.matches.emplace_back(f, f);
    return p;
  }

  std::map<uint32_t, TransferView> Views() const {
    std::map<uint32_t, TransferView> m;
    for (uint32_t v = 0; v < views_.size(); ++v) m[v] = {&views_[v].bearings, &views_[v].descriptors};
    return m;
  }

  std::vector<View> views_;
  std::vector<PairEstimate> pairs_;
};

TEST_F(ThirdViewTransfer, GivesTheMissingPartnersInTheThirdView) {
  GuidedMatchingOptions o;
  o.threshold_px = 2.0;
  const std::vector<int> added = TransferIntoThirdViews(&pairs_, Views(), kFocal, o);
  EXPECT_EQ(added[0], 0);  // (0, 1) already has every match
  EXPECT_GE(added[1], 150);
  EXPECT_EQ(added[1], added[2]);
  for (size_t p = 1; p < 3; ++p) {
    EXPECT_EQ(pairs_[p].matches.size(), kShared + static_cast<size_t>(added[p]));
    for (const auto& [a, b] : pairs_[p].matches) EXPECT_EQ(a, b) << "pair " << p;  // point a is feature a everywhere
  }
}

TEST_F(ThirdViewTransfer, NothingWhereTheThirdViewHasNoFeature) {
  // Image 2 without its features of points 40..199: only distractors are left there.
  for (int f = kShared; f < kPoints; ++f) views_[2].bearings[f] = Eigen::Vector3d(0, 0.7071, 0.7071);
  const std::vector<int> added = TransferIntoThirdViews(&pairs_, Views(), kFocal, GuidedMatchingOptions());
  EXPECT_EQ(added, (std::vector<int>{0, 0, 0}));
}

TEST_F(ThirdViewTransfer, NoTriangleWhenTheBaselinesDoNotClose) {
  pairs_[1].t_21 = -pairs_[1].t_21;
  EXPECT_EQ(TransferIntoThirdViews(&pairs_, Views(), kFocal, GuidedMatchingOptions()), (std::vector<int>{0, 0, 0}));
}

}  // namespace
}  // namespace pgba
