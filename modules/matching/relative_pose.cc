#include "modules/matching/relative_pose.h"

#include <ceres/ceres.h>
#include <ceres/rotation.h>
#include <ceres/sphere_manifold.h>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include <opengv/relative_pose/CentralRelativeAdapter.hpp>
#include <opengv/sac/Ransac.hpp>
#include <opengv/sac_problems/relative_pose/CentralRelativePoseSacProblem.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <utility>

#include "pgba/io/option_ranges.h"
#include "modules/matching/essential_ransac.h"
#include "pgba/optim/ceres_solver_options.h"
#include "modules/matching/opengv_rng.h"
#include "modules/matching/relative_pose_method.h"
#include "pgba/geometry/rotation.h"

namespace pgba {
namespace {

using SacProblem = opengv::sac_problems::relative_pose::CentralRelativePoseSacProblem;

// Squared norms entering the Sampson denominator for E = [t]x R: |(I - b1 b1^T) E^T b2|^2 =
// |b2 x t|^2 - g^2 and |(I - b2 b2^T) E b1|^2 = |t x R b1|^2 - g^2, with g = b2^T E b1
// (R preserves norms, so E^T b2 = R^T (b2 x t) needs no R^T).
template <typename T>
T SampsonAngleT(const T* Rb1, const T* t, const Eigen::Vector3d& b2) {
  T e[3];  // E b1 = t x (R b1)
  ceres::CrossProduct(t, Rb1, e);
  const T g = T(b2.x()) * e[0] + T(b2.y()) * e[1] + T(b2.z()) * e[2];
  const T b2v[3] = {T(b2.x()), T(b2.y()), T(b2.z())};
  T bt[3];
  ceres::CrossProduct(b2v, t, bt);
  const T denom = ceres::DotProduct(bt, bt) + ceres::DotProduct(e, e) - T(2.0) * g * g;
  if (!(denom > T(1e-300))) return T(0.0);
  return g / sqrt(denom);
}

// Sampson error in pixels of one correspondence; blocks (omega[3], t[3]) with
// R = R0 Exp(omega) (the project's right-multiplied increment) and t on the unit sphere.
struct SampsonResidual {
  SampsonResidual(const Eigen::Matrix3d& R0, const Eigen::Vector3d& b1, const Eigen::Vector3d& b2, double focal)
      : R0(R0), b1(b1), b2(b2), focal(focal) {}
  template <typename T>
  bool operator()(const T* omega, const T* t, T* residual) const {
    const T b[3] = {T(b1.x()), T(b1.y()), T(b1.z())};
    T y[3];
    ceres::AngleAxisRotatePoint(omega, b, y);
    T Rb1[3];
    for (int r = 0; r < 3; ++r) Rb1[r] = T(R0(r, 0)) * y[0] + T(R0(r, 1)) * y[1] + T(R0(r, 2)) * y[2];
    residual[0] = T(focal) * SampsonAngleT(Rb1, t, b2);
    return true;
  }
  Eigen::Matrix3d R0;
  Eigen::Vector3d b1, b2;
  double focal;
};

SacProblem::Algorithm ParseAlgorithm(const std::string& name) {
  return ParsePoseSolver(name) == PoseSolver::kNister ? SacProblem::NISTER : SacProblem::STEWENIUS;
}

// OpenGV's RANSAC with its sampling driven by our seeded engine (opengv_rng.h).
bool RunRansac(const std::vector<Eigen::Vector3d>& b1, const std::vector<Eigen::Vector3d>& b2, double threshold_angle,
               const RelativePoseOptions& options, Eigen::Matrix3d* R_21, Eigen::Vector3d* t_21, int* iterations) {
  if (ParsePoseScoring(options.scoring) == PoseScoring::kSampson) {
    EssentialRansacOptions o;
    o.threshold_angle = threshold_angle;
    o.algorithm = options.algorithm;
    o.max_iterations = options.max_iterations;
    o.confidence = options.confidence;
    o.seed = options.seed;
    const EssentialRansacResult r = EssentialRansac(b1, b2, o);
    *iterations = r.iterations;
    if (!r.success) return false;
    *R_21 = ClosestRotation(r.R_21);
    *t_21 = r.t_21.normalized();
    return true;
  }
  opengv::bearingVectors_t f1(b1.begin(), b1.end()), f2(b2.begin(), b2.end());
  opengv::relative_pose::CentralRelativeAdapter adapter(f1, f2);
  auto problem = std::make_shared<SacProblem>(adapter, ParseAlgorithm(options.algorithm), /*randomSeed=*/false);
  SeedSacProblem(options.seed, problem.get());
  opengv::sac::Ransac<SacProblem> ransac;
  ransac.sac_model_ = problem;
  ransac.threshold_ = 1.0 - std::cos(threshold_angle);
  ransac.max_iterations_ = options.max_iterations;
  ransac.probability_ = options.confidence;
  if (!ransac.computeModel(0)) return false;
  *iterations = ransac.iterations_;
  // OpenGV returns [R_12 | c_2 in frame 1]: x_1 = R_12 x_2 + c_2.
  const Eigen::Matrix3d R_12 = ransac.model_coefficients_.block<3, 3>(0, 0);
  const Eigen::Vector3d c2 = ransac.model_coefficients_.col(3);
  if (!R_12.allFinite() || !(c2.norm() > 0)) return false;
  *R_21 = ClosestRotation(R_12.transpose());
  *t_21 = -(*R_21 * c2).normalized();
  return true;
}

// Marks correspondences within the threshold and in front of both cameras; returns the count.
int Classify(const std::vector<Eigen::Vector3d>& b1, const std::vector<Eigen::Vector3d>& b2, const Eigen::Matrix3d& R,
             const Eigen::Vector3d& t, double threshold_angle, std::vector<uint8_t>* mask) {
  mask->assign(b1.size(), 0);
  int n = 0;
  for (size_t i = 0; i < b1.size(); ++i) {
    if (std::abs(SampsonAngle(R, t, b1[i], b2[i])) < threshold_angle && InFrontOfBoth(R, t, b1[i], b2[i], threshold_angle)) {
      (*mask)[i] = 1;
      ++n;
    }
  }
  return n;
}

void Refine(const std::vector<Eigen::Vector3d>& b1, const std::vector<Eigen::Vector3d>& b2,
            const std::vector<uint8_t>& mask, double focal, const RelativePoseOptions& options, Eigen::Matrix3d* R,
            Eigen::Vector3d* t) {
  std::vector<size_t> inliers;
  for (size_t i = 0; i < mask.size(); ++i)
    if (mask[i]) inliers.push_back(i);
  const size_t m = std::min(inliers.size(), static_cast<size_t>(std::max(options.max_refine_correspondences, 5)));
  if (m < 5) return;
  double omega[3] = {0, 0, 0};
  double tv[3] = {t->x(), t->y(), t->z()};
  ceres::Problem problem;
  ceres::LossFunction* loss = options.loss.CreateLossFunction();
  for (size_t k = 0; k < m; ++k) {
    const size_t i = inliers[k * inliers.size() / m];  // evenly spaced subsample
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<SampsonResidual, 1, 3, 3>(
                                 new SampsonResidual(*R, b1[i], b2[i], focal)),
                             loss, omega, tv);
  }
  problem.SetManifold(tv, new ceres::SphereManifold<3>());
  ceres::Solver::Summary summary;
  ceres::Solve(CeresSolverOptions(options.solver), &problem, &summary);
  if (!summary.IsSolutionUsable()) return;
  const Eigen::Matrix3d R_new = ClosestRotation(*R * ExpSO3(Eigen::Vector3d(omega[0], omega[1], omega[2])));
  const Eigen::Vector3d t_new = Eigen::Vector3d(tv[0], tv[1], tv[2]).normalized();
  if (R_new.allFinite() && t_new.allFinite()) {
    *R = R_new;
    *t = t_new;
  }
}

// Standard deviation (degrees, largest principal axis) of the rotation estimate: the
// Gauss-Newton covariance sigma^2 (J^T J)^-1 of the Sampson residuals (pixels) over the
// inliers, with J taken by central differences in the 5 degrees of freedom (omega: 3, the
// tangent plane of t: 2) and sigma the inliers' RMS residual. The rotation block of the
// inverse is the marginal, so rotation/translation coupling (a small or nearly planar patch
// of matches, where a rotation is mimicked by a translation) shows up as a large value.
double RotationSdDeg(const std::vector<Eigen::Vector3d>& b1, const std::vector<Eigen::Vector3d>& b2,
                     const std::vector<uint8_t>& mask, const Eigen::Matrix3d& R, const Eigen::Vector3d& t,
                     double focal) {
  Eigen::Vector3d u = t.unitOrthogonal(), v = t.cross(u);
  // The 11 poses the central differences evaluate (step +-h along each of the 5 degrees of
  // freedom, and the pose itself), made once instead of once per inlier: ExpSO3 and the
  // normalisation were most of this function's time.
  const auto perturbed = [&](const Eigen::Matrix<double, 5, 1>& d) {
    return std::make_pair(Eigen::Matrix3d(R * ExpSO3(d.head<3>())), Eigen::Vector3d((t + d(3) * u + d(4) * v).normalized()));
  };
  constexpr double h = 1e-6;
  std::pair<Eigen::Matrix3d, Eigen::Vector3d> plus[5], minus[5];
  for (int k = 0; k < 5; ++k) {
    Eigen::Matrix<double, 5, 1> d = Eigen::Matrix<double, 5, 1>::Zero();
    d(k) = h;
    plus[k] = perturbed(d);
    minus[k] = perturbed(-d);
  }
  const auto centre = perturbed(Eigen::Matrix<double, 5, 1>::Zero());
  const auto residual = [&](size_t i, const std::pair<Eigen::Matrix3d, Eigen::Vector3d>& pose) {
    return focal * SampsonAngle(pose.first, pose.second, b1[i], b2[i]);
  };
  Eigen::Matrix<double, 5, 5> JtJ = Eigen::Matrix<double, 5, 5>::Zero();
  double sum_sq = 0.0;
  int n = 0;
  for (size_t i = 0; i < mask.size(); ++i) {
    if (!mask[i]) continue;
    Eigen::Matrix<double, 5, 1> J;
    for (int k = 0; k < 5; ++k) J(k) = (residual(i, plus[k]) - residual(i, minus[k])) / (2 * h);
    JtJ += J * J.transpose();
    const double r = residual(i, centre);
    sum_sq += r * r;
    ++n;
  }
  if (n < 6) return std::numeric_limits<double>::infinity();
  const double sigma2 = sum_sq / (n - 5);
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 5, 5>> eig(JtJ);
  if (eig.info() != Eigen::Success || !(eig.eigenvalues()(0) > 1e-12 * eig.eigenvalues()(4)))
    return std::numeric_limits<double>::infinity();
  const Eigen::Matrix3d cov = sigma2 * JtJ.inverse().topLeftCorner<3, 3>();
  const double max_var = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(cov).eigenvalues()(2);
  return std::sqrt(std::max(max_var, 0.0)) * 180.0 / M_PI;
}

}  // namespace

double SampsonAngle(const Eigen::Matrix3d& R_21, const Eigen::Vector3d& t_21, const Eigen::Vector3d& b1,
                    const Eigen::Vector3d& b2) {
  const Eigen::Vector3d Rb1 = R_21 * b1;
  return SampsonAngleT<double>(Rb1.data(), t_21.data(), b2);
}

bool InFrontOfBoth(const Eigen::Matrix3d& R_21, const Eigen::Vector3d& t_21, const Eigen::Vector3d& b1,
                   const Eigen::Vector3d& b2, double parallel_angle_rad) {
  // Depths from the least-squares ray intersection in frame 2: l1 (R b1) + t = l2 b2.
  const Eigen::Vector3d a = R_21 * b1;
  const double ab = a.dot(b2);
  const double det = a.squaredNorm() * b2.squaredNorm() - ab * ab;
  if (std::sqrt(std::max(det, 0.0)) < std::sin(parallel_angle_rad)) return ab > 0;  // at infinity: same direction
  const double at = a.dot(t_21), bt = b2.dot(t_21);
  const double l1 = (-at * b2.squaredNorm() + ab * bt) / det;
  const double l2 = (a.squaredNorm() * bt - ab * at) / det;
  return l1 > 0 && l2 > 0;
}

namespace {

void CheckInputs(const std::vector<Eigen::Vector3d>& bearings1, const std::vector<Eigen::Vector3d>& bearings2,
                 double focal_px, const RelativePoseOptions& options, const char* caller) {
  if (bearings1.size() != bearings2.size())
    throw std::invalid_argument(std::string(caller) + ": bearing lists differ in size");
  if (!(focal_px > 0) || !(options.threshold_px > 0))
    throw std::invalid_argument(std::string(caller) + ": focal and threshold must be positive");
  for (size_t i = 0; i < bearings1.size(); ++i)
    if (!bearings1[i].allFinite() || !bearings2[i].allFinite())
      throw std::invalid_argument(std::string(caller) + ": non-finite bearing");
}

// RefineRelativePose from a pose fitted to other correspondences of the pair (the front
// end's, on its matches). Measured on a synthetic orbit from the truth disturbed by 0.1 deg
// (tests/triplets/pair_estimation_test.cc): refined on the inliers under the threshold alone, 106 of 387 pairs
// lost their consensus; after a first pass on those of 4x the threshold one did. That pass
// runs only when the threshold sees less than kRefineStartWellPlaced of the wide inliers (a
// front-end pose on the same features nearly always does). Then up to kRefineStartMaxPasses
// refine + re-classify passes, stopping early once a pass leaves the inliers unchanged and
// turns the rotation by less than kRefineConvergedDeg. One pass, measured by
// bench/reuse_geometry.sh: the Sampson refinement, not RANSAC, is most of a pair's cost
// (150-image aerial block: pairs stage 7.5 s estimated, 6.5 s refined, 1.7 s reused; 4
// passes take longer than RANSAC), and the final poses on the Strecha sets move by at most
// 6e-5 deg against the estimated pairs'. On the disturbed synthetic starts 4 passes reach
// RANSAC's 90th percentile of the rotation errors (0.205 deg), one 0.211 deg.
constexpr double kRefineStartThresholdFactor = 4.0;
constexpr double kRefineStartWellPlaced = 0.98;
constexpr int kRefineStartMaxPasses = 1;
constexpr double kRefineConvergedDeg = 1e-4;

// Everything after the minimal solver: inliers of (R, t), the refinement passes, the median
// triangulation angle and the rotation's standard deviation.
RelativePoseResult FinishFromModel(const std::vector<Eigen::Vector3d>& bearings1,
                                   const std::vector<Eigen::Vector3d>& bearings2, double focal_px,
                                   const RelativePoseOptions& options, int passes, bool stop_when_converged,
                                   Eigen::Matrix3d R, Eigen::Vector3d t, RelativePoseResult result) {
  const double threshold_angle = std::atan(options.threshold_px / focal_px);
  std::vector<uint8_t> mask;
  int n = Classify(bearings1, bearings2, R, t, threshold_angle, &mask);
  if (options.refine) {
    // Refine, re-classify with the better model, refine again on the new inlier set.
    for (int pass = 0; pass < passes && n >= 5; ++pass) {
      const Eigen::Matrix3d R_before = R;
      const std::vector<uint8_t> mask_before = mask;
      Refine(bearings1, bearings2, mask, focal_px, options, &R, &t);
      n = Classify(bearings1, bearings2, R, t, threshold_angle, &mask);
      if (stop_when_converged && mask == mask_before && RotationAngleDeg(R, R_before) < kRefineConvergedDeg) break;
    }
  }
  result.R_21 = R;
  result.t_21 = t;
  result.inlier_mask = std::move(mask);
  result.num_inliers = n;
  std::vector<double> angles;
  angles.reserve(n);
  for (size_t i = 0; i < bearings1.size(); ++i) {
    if (!result.inlier_mask[i]) continue;
    const Eigen::Vector3d a = R * bearings1[i];
    angles.push_back(std::atan2(a.cross(bearings2[i]).norm(), a.dot(bearings2[i])));
  }
  if (!angles.empty()) {
    std::nth_element(angles.begin(), angles.begin() + angles.size() / 2, angles.end());
    result.median_triangulation_angle_deg = angles[angles.size() / 2] * 180.0 / M_PI;
  }
  result.rotation_sd_deg = RotationSdDeg(bearings1, bearings2, result.inlier_mask, R, t, focal_px);
  result.success = n >= options.min_inliers;
  return result;
}

}  // namespace

RelativePoseResult EstimateRelativePose(const std::vector<Eigen::Vector3d>& bearings1,
                                        const std::vector<Eigen::Vector3d>& bearings2, double focal_px,
                                        const RelativePoseOptions& options) {
  CheckInputs(bearings1, bearings2, focal_px, options, "EstimateRelativePose");
  RelativePoseResult result;
  result.inlier_mask.assign(bearings1.size(), 0);
  // 5 points for the solver + 3 that OpenGV uses to pick among its solutions.
  if (bearings1.size() < 8 || static_cast<int>(bearings1.size()) < options.min_inliers) return result;

  const double threshold_angle = std::atan(options.threshold_px / focal_px);
  Eigen::Matrix3d R;
  Eigen::Vector3d t;
  if (!RunRansac(bearings1, bearings2, threshold_angle, options, &R, &t, &result.ransac_iterations)) return result;
  return FinishFromModel(bearings1, bearings2, focal_px, options, std::max(options.refine_passes, 1), options.refine_until_converged, R, t,
                         std::move(result));
}

RelativePoseResult RefineRelativePose(const std::vector<Eigen::Vector3d>& bearings1,
                                      const std::vector<Eigen::Vector3d>& bearings2, double focal_px,
                                      const RelativePoseOptions& options, const Eigen::Matrix3d& R_21,
                                      const Eigen::Vector3d& t_21) {
  CheckInputs(bearings1, bearings2, focal_px, options, "RefineRelativePose");
  if (!R_21.allFinite() || !t_21.allFinite() || !(t_21.norm() > 0))
    throw std::invalid_argument("RefineRelativePose: non-finite or zero starting pose");
  RelativePoseResult result;
  result.inlier_mask.assign(bearings1.size(), 0);
  if (static_cast<int>(bearings1.size()) < std::max(options.min_inliers, 5)) return result;
  // The start was fitted to other correspondences: under the threshold it may see only part
  // of these inliers (a 0.1 degree rotation is 1.7 px at f = 1000), and a refinement on that
  // part can settle elsewhere. Then one pass on the consensus of a wider threshold first.
  Eigen::Matrix3d R = ClosestRotation(R_21);
  Eigen::Vector3d t = t_21.normalized();
  if (options.refine) {
    std::vector<uint8_t> wide_mask, mask;
    const double wide = std::atan(kRefineStartThresholdFactor * options.threshold_px / focal_px);
    const int n_wide = Classify(bearings1, bearings2, R, t, wide, &wide_mask);
    const int n = Classify(bearings1, bearings2, R, t, std::atan(options.threshold_px / focal_px), &mask);
    if (n_wide >= 5 && n < kRefineStartWellPlaced * n_wide)
      Refine(bearings1, bearings2, wide_mask, focal_px, options, &R, &t);
  }
  return FinishFromModel(bearings1, bearings2, focal_px, options, kRefineStartMaxPasses, /*stop_when_converged=*/true,
                         R, t, std::move(result));
}

std::string RelativePoseOptions::Check() const {
  if (const std::string m = CheckRanges(*this, "pairs.relative_pose"); !m.empty()) return m;
  return "";
}

}  // namespace pgba
