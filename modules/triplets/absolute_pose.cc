#include "modules/triplets/absolute_pose.h"

#include <opengv/absolute_pose/CentralAbsoluteAdapter.hpp>
#include <opengv/absolute_pose/methods.hpp>
#include <opengv/sac/Ransac.hpp>
#include <opengv/sac_problems/absolute_pose/AbsolutePoseSacProblem.hpp>

#include <cmath>
#include <memory>
#include <stdexcept>

#include "pgba/io/option_ranges.h"
#include "modules/matching/opengv_rng.h"
#include "pgba/geometry/rotation.h"

namespace pgba {
namespace {

using SacProblem = opengv::sac_problems::absolute_pose::AbsolutePoseSacProblem;

SacProblem::Algorithm ParseAlgorithm(const std::string& name) {
  if (name == "p3p_kneip") return SacProblem::KNEIP;
  if (name == "p3p_gao") return SacProblem::GAO;
  if (name == "epnp") return SacProblem::EPNP;
  throw std::invalid_argument("unknown absolute pose algorithm '" + name + "' (p3p_kneip, p3p_gao, epnp)");
}

// OpenGV's [R | t]: camera-to-world rotation and camera position.
Pose FromOpenGv(const opengv::transformation_t& T) {
  return Pose::FromRC(ClosestRotation(T.block<3, 3>(0, 0).transpose()), T.col(3));
}

}  // namespace

AbsolutePoseResult EstimateAbsolutePose(const std::vector<Eigen::Vector3d>& bearings,
                                        const std::vector<Eigen::Vector3d>& points, double focal_px,
                                        const AbsolutePoseOptions& options) {
  if (bearings.size() != points.size()) throw std::invalid_argument("EstimateAbsolutePose: size mismatch");
  if (!(focal_px > 0) || !(options.threshold_px > 0))
    throw std::invalid_argument("EstimateAbsolutePose: focal and threshold must be positive");
  const SacProblem::Algorithm algorithm = ParseAlgorithm(options.algorithm);
  AbsolutePoseResult result;
  result.inlier_mask.assign(bearings.size(), 0);
  const int n = static_cast<int>(bearings.size());
  if (n < std::max(6, options.min_inliers)) return result;

  opengv::bearingVectors_t f(bearings.begin(), bearings.end());
  opengv::points_t X(points.begin(), points.end());
  opengv::absolute_pose::CentralAbsoluteAdapter adapter(f, X);
  auto problem = std::make_shared<SacProblem>(adapter, algorithm, /*randomSeed=*/false);
  SeedSacProblem(options.seed, problem.get());
  opengv::sac::Ransac<SacProblem> ransac;
  ransac.sac_model_ = problem;
  const double threshold = 1.0 - std::cos(std::atan(options.threshold_px / focal_px));
  ransac.threshold_ = threshold;
  ransac.max_iterations_ = options.max_iterations;
  ransac.probability_ = options.confidence;
  if (!ransac.computeModel(0) || static_cast<int>(ransac.inliers_.size()) < 6) return result;

  // Nonlinear refinement on the inliers, then the inliers of the refined pose.
  adapter.setR(ransac.model_coefficients_.block<3, 3>(0, 0));
  adapter.sett(ransac.model_coefficients_.col(3));
  const opengv::transformation_t refined = opengv::absolute_pose::optimize_nonlinear(adapter, ransac.inliers_);
  const opengv::transformation_t& T = refined.allFinite() ? refined : ransac.model_coefficients_;
  result.pose = FromOpenGv(T);
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d xc = result.pose.ToCamera(points[i]);
    if (xc.z() > 0 && 1.0 - bearings[i].dot(xc.normalized()) < threshold) {
      result.inlier_mask[i] = 1;
      ++result.num_inliers;
    }
  }
  result.success = result.num_inliers >= options.min_inliers;
  return result;
}

std::string AbsolutePoseOptions::Check() const {
  if (const std::string m = CheckRanges(*this, "triplets.absolute_pose"); !m.empty()) return m;
  return "";
}

}  // namespace pgba
