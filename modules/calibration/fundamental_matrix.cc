#include "modules/calibration/fundamental_matrix.h"

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <opencv2/calib3d.hpp>
#include <stdexcept>

#include "pgba/io/option_ranges.h"

namespace pgba {
namespace {

// Hartley's normalisation: centroid to the origin, mean distance sqrt(2) (H&Z 4.4.4).
Eigen::Matrix3d NormalisingTransform(const std::vector<Eigen::Vector2d>& x) {
  Eigen::Vector2d c = Eigen::Vector2d::Zero();
  for (const auto& p : x) c += p;
  c /= static_cast<double>(x.size());
  double d = 0.0;
  for (const auto& p : x) d += (p - c).norm();
  d /= static_cast<double>(x.size());
  const double s = d > 0 ? std::sqrt(2.0) / d : 1.0;
  Eigen::Matrix3d T;
  T << s, 0, -s * c.x(), 0, s, -s * c.y(), 0, 0, 1;
  return T;
}

Eigen::Matrix3d NearestRankTwo(const Eigen::Matrix3d& F) {
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(F, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Vector3d s = svd.singularValues();
  s(2) = 0.0;
  return svd.matrixU() * s.asDiagonal() * svd.matrixV().transpose();
}

// Weighted normalised 8-point on the correspondences with weight > 0 (H&Z alg. 11.1).
Eigen::Matrix3d WeightedEightPoint(const std::vector<Eigen::Vector2d>& x1, const std::vector<Eigen::Vector2d>& x2,
                                   const std::vector<double>& weight, const Eigen::Matrix3d& T1,
                                   const Eigen::Matrix3d& T2) {
  Eigen::Matrix<double, 9, 9> AtA = Eigen::Matrix<double, 9, 9>::Zero();
  for (size_t i = 0; i < x1.size(); ++i) {
    if (!(weight[i] > 0)) continue;
    const Eigen::Vector3d a = T1 * x1[i].homogeneous(), b = T2 * x2[i].homogeneous();
    Eigen::Matrix<double, 9, 1> row;  // x2^T F x1 = sum_rc b_r F_rc a_c, F row-major
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) row(3 * r + c) = b(r) * a(c);
    AtA.noalias() += weight[i] * row * row.transpose();
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 9, 9>> eig(AtA);
  const Eigen::Matrix<double, 9, 1> f = eig.eigenvectors().col(0);  // smallest eigenvalue
  Eigen::Matrix3d Fn;
  Fn << f(0), f(1), f(2), f(3), f(4), f(5), f(6), f(7), f(8);
  const Eigen::Matrix3d F = T2.transpose() * NearestRankTwo(Fn) * T1;  // back to pixels
  return F / F.norm();
}

}  // namespace

std::string FundamentalMatrixOptions::Check() const {
  if (const std::string m = CheckRanges(*this, "calibration.fundamental"); !m.empty()) return m;
  return "";
}

double SampsonDistance(const Eigen::Matrix3d& F, const Eigen::Vector2d& x1, const Eigen::Vector2d& x2) {
  const Eigen::Vector3d a = x1.homogeneous(), b = x2.homogeneous();
  const Eigen::Vector3d Fa = F * a, Ftb = F.transpose() * b;
  const double denom = Fa.head<2>().squaredNorm() + Ftb.head<2>().squaredNorm();
  return denom > 0 ? std::abs(b.dot(Fa)) / std::sqrt(denom) : INFINITY;
}

FundamentalMatrixResult EstimateFundamentalMatrix(const std::vector<Eigen::Vector2d>& x1,
                                                  const std::vector<Eigen::Vector2d>& x2,
                                                  const FundamentalMatrixOptions& options) {
  if (x1.size() != x2.size()) throw std::invalid_argument("EstimateFundamentalMatrix: mismatched correspondences");
  const size_t n = x1.size();
  if (n < static_cast<size_t>(std::max(8, options.min_inliers))) {
    FundamentalMatrixResult none;
    none.inlier_mask.assign(n, 0);
    return none;
  }
  std::vector<cv::Point2d> p1(n), p2(n);
  for (size_t i = 0; i < n; ++i) {
    p1[i] = {x1[i].x(), x1[i].y()};
    p2[i] = {x2[i].x(), x2[i].y()};
  }
  cv::Mat mask;
  const cv::Mat Fcv = cv::findFundamentalMat(p1, p2, cv::FM_RANSAC, options.threshold_px, options.confidence,
                                             options.max_iterations, mask);
  if (Fcv.rows != 3 || Fcv.cols != 3) {  // no model (or several: 7 points exactly)
    FundamentalMatrixResult none;
    none.inlier_mask.assign(n, 0);
    return none;
  }
  Eigen::Matrix3d F;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) F(r, c) = Fcv.at<double>(r, c);
  return RefineFundamentalMatrix(x1, x2, F, options);
}

FundamentalMatrixResult RefineFundamentalMatrix(const std::vector<Eigen::Vector2d>& x1,
                                                const std::vector<Eigen::Vector2d>& x2, const Eigen::Matrix3d& initial,
                                                const FundamentalMatrixOptions& options) {
  if (x1.size() != x2.size()) throw std::invalid_argument("RefineFundamentalMatrix: mismatched correspondences");
  FundamentalMatrixResult result;
  const size_t n = x1.size();
  const int min_inliers = std::max(8, options.min_inliers);
  result.inlier_mask.assign(n, 0);
  if (n < static_cast<size_t>(min_inliers) || !(initial.norm() > 0)) return result;
  Eigen::Matrix3d F = initial / initial.norm();

  const auto mark_inliers = [&](const Eigen::Matrix3d& model) {
    int count = 0;
    for (size_t i = 0; i < n; ++i) {
      result.inlier_mask[i] = SampsonDistance(model, x1[i], x2[i]) <= options.threshold_px;
      count += result.inlier_mask[i];
    }
    return count;
  };
  int inliers = mark_inliers(F);
  if (inliers < min_inliers) return result;

  const Eigen::Matrix3d T1 = NormalisingTransform(x1), T2 = NormalisingTransform(x2);
  std::vector<double> weight(n, 0.0);
  for (int it = 0; it < options.refine_iterations; ++it) {
    // Weight 1 / (Sampson denominator) turns the algebraic residual x2^T F x1 into the
    // Sampson distance; the Huber factor bounds the pull of inliers far from the model.
    for (size_t i = 0; i < n; ++i) {
      weight[i] = 0.0;
      if (!result.inlier_mask[i]) continue;
      const Eigen::Vector3d a = x1[i].homogeneous(), b = x2[i].homogeneous();
      const Eigen::Vector3d Fa = F * a, Ftb = F.transpose() * b;
      const double denom = Fa.head<2>().squaredNorm() + Ftb.head<2>().squaredNorm();
      if (!(denom > 0)) continue;
      const double d = std::abs(b.dot(Fa)) / std::sqrt(denom);
      weight[i] = (d <= options.huber_px ? 1.0 : options.huber_px / d) / denom;
    }
    const Eigen::Matrix3d refined = WeightedEightPoint(x1, x2, weight, T1, T2);
    if (!refined.allFinite()) break;
    F = refined;
    inliers = mark_inliers(F);
    if (inliers < min_inliers) return result;
  }
  double sum2 = 0.0;
  for (size_t i = 0; i < n; ++i)
    if (result.inlier_mask[i]) sum2 += std::pow(SampsonDistance(F, x1[i], x2[i]), 2);
  result.success = true;
  result.F = F;
  result.num_inliers = inliers;
  result.rms_sampson_px = std::sqrt(sum2 / inliers);
  return result;
}

}  // namespace pgba
