// Fundamental matrix estimation (fundamental_matrix.h) against an exact two-view truth:
// F_true = K2^-T [t]x R K1^-1 (H&Z eq. 9.6 with E = [t]x R), pixels projected through known
// cameras, with noise and outliers.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

#include "modules/calibration/fundamental_matrix.h"

namespace pgba {
namespace {

struct TwoViews {
  Eigen::Matrix3d F;  // unit Frobenius norm
  std::vector<Eigen::Vector2d> x1, x2;
  std::vector<bool> outlier;
};

Eigen::Matrix3d Skew(const Eigen::Vector3d& t) {
  Eigen::Matrix3d S;
  S << 0, -t.z(), t.y(), t.z(), 0, -t.x(), -t.y(), t.x(), 0;
  return S;
}

// Points in a 4 m deep box 5 m in front of camera 1; camera 2 rotated 12 degrees and moved
// sideways (general position: the optical axes do not meet).
TwoViews MakeTwoViews(int n, double noise_px, double outlier_fraction, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  std::normal_distribution<double> gauss(0.0, 1.0);
  Eigen::Matrix3d K1, K2;
  K1 << 1000, 0, 640, 0, 1000, 480, 0, 0, 1;
  K2 << 1150, 0, 600, 0, 1150, 500, 0, 0, 1;
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.21, Eigen::Vector3d(0.2, 1.0, 0.1).normalized()).toRotationMatrix();
  const Eigen::Vector3d t(-1.0, 0.1, 0.25);  // x2 = R x1 + t
  TwoViews v;
  const Eigen::Matrix3d F = K2.inverse().transpose() * Skew(t) * R * K1.inverse();
  v.F = F / F.norm();
  while (static_cast<int>(v.x1.size()) < n) {
    const Eigen::Vector3d X(2.5 * uni(rng), 2.0 * uni(rng), 7.0 + 2.0 * uni(rng));
    const Eigen::Vector3d X2 = R * X + t;
    if (X2.z() <= 0) continue;
    Eigen::Vector2d p1 = (K1 * X).hnormalized(), p2 = (K2 * X2).hnormalized();
    const bool out = uni(rng) < 2 * outlier_fraction - 1;
    if (out) p2 = Eigen::Vector2d(640 + 600 * uni(rng), 480 + 450 * uni(rng));
    v.x1.push_back(p1 + noise_px * Eigen::Vector2d(gauss(rng), gauss(rng)));
    v.x2.push_back(p2 + noise_px * Eigen::Vector2d(gauss(rng), gauss(rng)));
    v.outlier.push_back(out);
  }
  return v;
}

// Distance of the estimate from the truth up to sign.
double FDistance(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) { return std::min((a - b).norm(), (a + b).norm()); }

TEST(FundamentalMatrix, ExactCorrespondencesGiveTheTrueMatrix) {
  const TwoViews v = MakeTwoViews(200, 0.0, 0.0, 1);
  const FundamentalMatrixResult r = EstimateFundamentalMatrix(v.x1, v.x2, {});
  ASSERT_TRUE(r.success);
  EXPECT_EQ(r.num_inliers, 200);
  EXPECT_LT(FDistance(r.F, v.F), 1e-6);
  EXPECT_LT(r.rms_sampson_px, 1e-6);
  EXPECT_NEAR(Eigen::JacobiSVD<Eigen::Matrix3d>(r.F).singularValues()(2), 0.0, 1e-12);  // rank 2
}

TEST(FundamentalMatrix, NoiseAndOutliers) {
  const TwoViews v = MakeTwoViews(400, 0.5, 0.25, 2);
  const FundamentalMatrixResult r = EstimateFundamentalMatrix(v.x1, v.x2, {});
  ASSERT_TRUE(r.success);
  int true_outliers_kept = 0, inliers_lost = 0;
  for (size_t i = 0; i < v.x1.size(); ++i) {
    true_outliers_kept += v.outlier[i] && r.inlier_mask[i];
    inliers_lost += !v.outlier[i] && !r.inlier_mask[i];
  }
  // An outlier that happens to fall near its epipolar line is indistinguishable (a few %).
  EXPECT_LE(true_outliers_kept, 6);
  EXPECT_LE(inliers_lost, 3);
  // Sampson distances at the noise level (0.5 px per coordinate: ~0.5 px across the line).
  EXPECT_GT(r.rms_sampson_px, 0.3);
  EXPECT_LT(r.rms_sampson_px, 0.6);
  // The refinement brings the model close to the truth: the true correspondences' mean
  // Sampson distance under the estimate is within a small fraction of a pixel of the truth's.
  double est = 0, truth = 0;
  int n = 0;
  for (size_t i = 0; i < v.x1.size(); ++i) {
    if (v.outlier[i]) continue;
    est += SampsonDistance(r.F, v.x1[i], v.x2[i]);
    truth += SampsonDistance(v.F, v.x1[i], v.x2[i]);
    ++n;
  }
  EXPECT_LT(est / n, truth / n + 0.02);
  // Without the refinement (the RANSAC model) it is worse.
  FundamentalMatrixOptions raw;
  raw.refine_iterations = 0;
  const FundamentalMatrixResult r0 = EstimateFundamentalMatrix(v.x1, v.x2, raw);
  ASSERT_TRUE(r0.success);
  EXPECT_LT(FDistance(r.F, v.F), FDistance(r0.F, v.F));
}

TEST(FundamentalMatrix, TooFewCorrespondencesAndBadInput) {
  const TwoViews v = MakeTwoViews(20, 0.0, 0.0, 3);
  EXPECT_FALSE(EstimateFundamentalMatrix(v.x1, v.x2, {}).success);  // min_inliers 30
  FundamentalMatrixOptions few;
  few.min_inliers = 8;
  EXPECT_TRUE(EstimateFundamentalMatrix(v.x1, v.x2, few).success);
  std::vector<Eigen::Vector2d> shorter(v.x2.begin(), v.x2.end() - 1);
  EXPECT_THROW(EstimateFundamentalMatrix(v.x1, shorter, {}), std::invalid_argument);
  FundamentalMatrixOptions bad;
  EXPECT_EQ(bad.Check(), "");
  bad.min_inliers = 7;
  EXPECT_NE(bad.Check().find("min_inliers"), std::string::npos);
  bad = {};
  bad.confidence = 1.0;
  EXPECT_NE(bad.Check().find("confidence"), std::string::npos);
}

}  // namespace
}  // namespace pgba
