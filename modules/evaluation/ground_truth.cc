#include "evaluation/ground_truth.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <map>

#include "pgba/io/option_ranges.h"
#include "evaluation/statistics.h"
#include "pgba/geometry/rotation.h"

namespace pgba {

double SceneExtent(const Reconstruction& rec) {
  std::vector<Eigen::Vector3d> c;
  c.reserve(rec.images.size());
  for (const auto& [id, im] : rec.images) c.push_back(im.pose.C());
  // O(n^2) is a few milliseconds even for 5,000 images; an exact diameter keeps the
  // definition simple.
  double best2 = 0.0;
  for (size_t i = 0; i < c.size(); ++i)
    for (size_t j = i + 1; j < c.size(); ++j) best2 = std::max(best2, (c[i] - c[j]).squaredNorm());
  return std::sqrt(best2);
}

namespace {

// Sim(3) from the centres flagged in `use`; false if degenerate.
bool AlignSubset(const std::vector<Eigen::Vector3d>& est, const std::vector<Eigen::Vector3d>& truth,
                 const std::vector<bool>& use, Sim3* sim) {
  std::vector<Eigen::Vector3d> src, dst;
  for (size_t i = 0; i < est.size(); ++i)
    if (use[i]) {
      src.push_back(est[i]);
      dst.push_back(truth[i]);
    }
  return EstimateSim3(src, dst, sim);
}

std::vector<double> CentreErrors(const Sim3& sim, const std::vector<Eigen::Vector3d>& est,
                                 const std::vector<Eigen::Vector3d>& truth) {
  std::vector<double> e(est.size());
  for (size_t i = 0; i < est.size(); ++i) e[i] = (sim.Apply(est[i]) - truth[i]).norm();
  return e;
}

// Second / first singular value of the centred points (0 for collinear points).
double Collinearity(const std::vector<Eigen::Vector3d>& c, Eigen::Vector3d* axis) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& x : c) mean += x;
  mean /= std::max<size_t>(1, c.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const auto& x : c) cov += (x - mean) * (x - mean).transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
  *axis = eig.eigenvectors().col(2);
  const double l1 = eig.eigenvalues()(2), l2 = std::max(0.0, eig.eigenvalues()(1));
  return l1 > 0 ? std::sqrt(l2 / l1) : 0.0;
}

}  // namespace

void RelativePoseErrors(const std::vector<Pose>& est, const std::vector<Pose>& truth, GroundTruthErrors* out) {
  const size_t n = std::min(est.size(), truth.size());
  std::vector<double> rot, dir;
  rot.reserve(n * (n - 1) / 2 + 1);
  dir.reserve(n * (n - 1) / 2 + 1);
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Matrix3d Ri = est[i].R(), Ri_gt = truth[i].R();
    for (size_t j = i + 1; j < n; ++j) {
      rot.push_back(RotationAngleDeg(est[j].R() * Ri.transpose(), truth[j].R() * Ri_gt.transpose()));
      const Eigen::Vector3d d = Ri * (est[j].C() - est[i].C());
      const Eigen::Vector3d d_gt = Ri_gt * (truth[j].C() - truth[i].C());
      // A pair with coincident centres has no direction: it is left out of that metric only.
      if (d.norm() > 0 && d_gt.norm() > 0)
        dir.push_back(std::atan2(d.cross(d_gt).norm(), d.dot(d_gt)) * 180.0 / M_PI);
    }
  }
  out->num_pairs = rot.size();
  out->rel_rot_err_deg_median = rot.empty() ? 0.0 : Median(rot);
  out->rel_rot_err_deg_max = rot.empty() ? 0.0 : Max(rot);
  out->rel_dir_err_deg_median = dir.empty() ? 0.0 : Median(dir);
  out->rel_dir_err_deg_max = dir.empty() ? 0.0 : Max(dir);
}

GroundTruthErrors CompareToGroundTruth(const Reconstruction& model, const Reconstruction& gt,
                                       const GroundTruthOptions& options) {
  GroundTruthErrors out;
  out.scene_extent = SceneExtent(gt);
  std::vector<const Image*> est_images, gt_images;
  for (const auto& [id, im] : model.images) {
    const auto gt_id = gt.FindImageByName(im.name);
    if (!gt_id) continue;
    est_images.push_back(&im);
    gt_images.push_back(&gt.images.at(*gt_id));
  }
  out.num_common = est_images.size();
  std::vector<Eigen::Vector3d> est(out.num_common), truth(out.num_common);
  for (size_t i = 0; i < out.num_common; ++i) {
    est[i] = est_images[i]->pose.C();
    truth[i] = gt_images[i]->pose.C();
  }

  {
    std::vector<Pose> est_poses, gt_poses;
    for (size_t i = 0; i < out.num_common; ++i) {
      est_poses.push_back(est_images[i]->pose);
      gt_poses.push_back(gt_images[i]->pose);
    }
    RelativePoseErrors(est_poses, gt_poses, &out);
  }

  std::vector<bool> use(out.num_common, true);
  if (!AlignSubset(est, truth, use, &out.alignment) || !(out.scene_extent > 0)) return out;
  for (int round = 0; round < options.max_rounds; ++round) {
    const std::vector<double> err = CentreErrors(out.alignment, est, truth);
    // The floor keeps an exact alignment (median error ~ 1e-16) from rejecting centres over
    // rounding noise.
    const double threshold = std::max(options.outlier_factor * Median(err), 1e-9 * out.scene_extent);
    std::vector<bool> keep(out.num_common);
    for (size_t i = 0; i < err.size(); ++i) keep[i] = err[i] <= threshold;
    if (keep == use) break;
    Sim3 refined;
    if (!AlignSubset(est, truth, keep, &refined)) break;  // too few or degenerate inliers
    use = keep;
    out.alignment = refined;
  }
  out.num_alignment_inliers = static_cast<size_t>(std::count(use.begin(), use.end(), true));

  // Reported so that a reader can tell when the centre alignment's rotation about the
  // centres' main line (a strip, a video along a wall) is weakly determined.
  Eigen::Vector3d axis;
  out.collinearity = Collinearity(truth, &axis);

  const std::vector<double> centre_err = CentreErrors(out.alignment, est, truth);
  for (size_t i = 0; i < out.num_common; ++i) {
    out.names.push_back(est_images[i]->name);
    out.rot_err_deg.push_back(
        RotationAngleDeg(est_images[i]->pose.R() * out.alignment.R.transpose(), gt_images[i]->pose.R()));
    out.center_err_rel.push_back(centre_err[i] / out.scene_extent);
  }
  out.rot_err_deg_median = Median(out.rot_err_deg);
  out.rot_err_deg_max = Max(out.rot_err_deg);
  out.center_err_rel_median = Median(out.center_err_rel);
  out.center_err_rel_max = Max(out.center_err_rel);
  out.ok = true;
  return out;
}

std::string GroundTruthOptions::Check() const {
  return CheckRanges(*this, "GroundTruthOptions");
}

}  // namespace pgba
