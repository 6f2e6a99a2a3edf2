#include "modules/triplets/intrinsics_uncertainty.h"

#include <Eigen/Cholesky>
#include <Eigen/Dense>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <set>

#include "pgba/optim/pose_parameterization.h"

namespace pgba {

double CornerPixelSensitivity(const Camera& camera, const Eigen::VectorXd& direction) {
  double best = 0.0;
  for (const Eigen::Vector2d& corner :
       {Eigen::Vector2d(0, 0), Eigen::Vector2d(camera.width, 0), Eigen::Vector2d(0, camera.height),
        Eigen::Vector2d(camera.width, camera.height)}) {
    const Eigen::Vector3d ray = camera.PixelToBearing(corner);
    // Central difference over the parameter (projections are smooth in every parameter);
    // the step is relative to the parameter's size, absolute for coefficients near 0.
    double size = 1.0;  // of the parameters the unknown moves
    for (int i = 0; i < direction.size(); ++i)
      if (direction(i) != 0.0) size = std::max(size, std::abs(camera.params[i]));
    const double h = 1e-6 * size;
    std::vector<double> plus = camera.params, minus = camera.params;
    for (int i = 0; i < direction.size(); ++i) {
      plus[i] += h * direction(i);
      minus[i] -= h * direction(i);
    }
    double p[2], m[2];
    ProjectToPixel(camera.model, plus.data(), ray.data(), p);
    ProjectToPixel(camera.model, minus.data(), ray.data(), m);
    best = std::max(best, std::hypot(p[0] - m[0], p[1] - m[1]) / (2.0 * h));
  }
  return best;
}

IntrinsicsUncertainty EstimateIntrinsicsUncertainty(const Reconstruction& rec, const std::vector<uint32_t>& image_ids,
                                                    const FreeIntrinsics& free, uint32_t gauge_anchor,
                                                    uint32_t gauge_scale) {
  IntrinsicsUncertainty out;
  out.max_stddev_px = std::numeric_limits<double>::infinity();
  // Columns: 6 per image ([C, omega] around its rotation, pose_parameterization.h), then the
  // free parameters of the cameras the images use.
  std::map<uint32_t, int> pose_col, camera_col;
  for (uint32_t id : image_ids) pose_col.emplace(id, 6 * static_cast<int>(pose_col.size()));
  std::set<uint32_t> used;
  for (uint32_t id : image_ids) used.insert(rec.images.at(id).camera_id);
  int cols = 6 * static_cast<int>(image_ids.size());
  for (const auto& [camera_id, indices] : free)
    if (used.count(camera_id)) camera_col[camera_id] = cols, cols += static_cast<int>(indices.size());
  const int num_pose_cols = 6 * static_cast<int>(image_ids.size());
  if (cols == num_pose_cols) return out;

  Eigen::MatrixXd S = Eigen::MatrixXd::Zero(cols, cols);
  for (const auto& [pid, point] : rec.points3D) {
    Eigen::Matrix3d Hpp = Eigen::Matrix3d::Zero();
    Eigen::MatrixXd Hcp = Eigen::MatrixXd::Zero(cols, 3);
    Eigen::MatrixXd Hcc = Eigen::MatrixXd::Zero(cols, cols);
    int views = 0;
    for (const TrackElement& el : point.track) {
      const auto pc = pose_col.find(el.image_id);
      if (pc == pose_col.end()) continue;
      const Image& image = rec.images.at(el.image_id);
      const Camera& camera = rec.CameraOf(image);
      const Eigen::Matrix3d R = image.pose.R();
      std::unique_ptr<ceres::CostFunction> cost(
          CreateReprojectionErrorWithIntrinsics(camera.model, R, image.points2D.at(el.point2D_idx).xy));
      PoseVector pose = PoseVector::Zero();
      pose.head<3>() = image.pose.C();
      const double* parameters[3] = {pose.data(), point.xyz.data(), camera.params.data()};
      const int n = static_cast<int>(camera.params.size());
      Eigen::Matrix<double, 2, 6, Eigen::RowMajor> Jc;
      Eigen::Matrix<double, 2, 3, Eigen::RowMajor> Jp;
      Eigen::Matrix<double, 2, Eigen::Dynamic, Eigen::RowMajor> Jk(2, n);
      double residual[2];
      double* jacobians[3] = {Jc.data(), Jp.data(), Jk.data()};
      if (!cost->Evaluate(parameters, residual, jacobians)) continue;
      // The observation's row block over all columns (points apart).
      Eigen::MatrixXd J = Eigen::MatrixXd::Zero(2, cols);
      J.middleCols<6>(pc->second) = Jc;
      if (const auto cc = camera_col.find(image.camera_id); cc != camera_col.end()) {
        const std::vector<int>& indices = free.at(image.camera_id);
        J.middleCols(cc->second, static_cast<int>(indices.size())) = Jk * IntrinsicDirections(camera, indices);
      }
      Hcc.noalias() += J.transpose() * J;
      Hcp.noalias() += J.transpose() * Jp;
      Hpp.noalias() += Jp.transpose() * Jp;
      ++views;
    }
    if (views < 2) continue;
    // Schur complement on the point (its 3x3 block is invertible for a triangulated point
    // seen twice; one at infinity contributes nothing it could determine).
    const Eigen::LDLT<Eigen::Matrix3d> ldlt(Hpp);
    if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 1e-12 * Hpp.trace())) continue;
    S += Hcc - Hcp * ldlt.solve(Hcp.transpose());
  }

  // Gauge: the anchor's 6 columns go; the scale image's centre keeps only the two directions
  // orthogonal to its baseline (OffsetSphereManifold of the triplet BA).
  std::vector<Eigen::VectorXd> basis;
  auto unit = [cols](int c) {
    Eigen::VectorXd e = Eigen::VectorXd::Zero(cols);
    e(c) = 1.0;
    return e;
  };
  const Eigen::Vector3d baseline =
      (rec.images.at(gauge_scale).pose.C() - rec.images.at(gauge_anchor).pose.C()).normalized();
  Eigen::Matrix3d frame = Eigen::Matrix3d::Identity() - baseline * baseline.transpose();
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(frame, Eigen::ComputeFullU);
  for (uint32_t id : image_ids) {
    const int c = pose_col.at(id);
    if (id == gauge_anchor) continue;
    for (int k = 0; k < 3; ++k) {
      if (id != gauge_scale) {
        basis.push_back(unit(c + k));
      } else if (k < 2) {
        Eigen::VectorXd e = Eigen::VectorXd::Zero(cols);
        e.segment<3>(c) = svd.matrixU().col(k);
        basis.push_back(e);
      }
    }
    for (int k = 3; k < 6; ++k) basis.push_back(unit(c + k));
  }
  const int first_intrinsic = static_cast<int>(basis.size());
  for (int c = num_pose_cols; c < cols; ++c) basis.push_back(unit(c));
  Eigen::MatrixXd T(cols, basis.size());
  for (size_t k = 0; k < basis.size(); ++k) T.col(static_cast<int>(k)) = basis[k];
  const Eigen::MatrixXd reduced = T.transpose() * S * T;
  // Jacobi-scaled so that pixels, radians and focal units do not decide the pivots.
  const Eigen::VectorXd scale = reduced.diagonal().cwiseMax(1e-300).cwiseSqrt().cwiseInverse();
  const Eigen::MatrixXd scaled = scale.asDiagonal() * reduced * scale.asDiagonal();
  const Eigen::LLT<Eigen::MatrixXd> llt(scaled);
  if (llt.info() != Eigen::Success) return out;
  const Eigen::MatrixXd cov =
      scale.asDiagonal() * llt.solve(Eigen::MatrixXd::Identity(scaled.rows(), scaled.cols())) * scale.asDiagonal();
  out.ok = true;
  out.max_stddev_px = 0.0;
  int k = first_intrinsic;
  for (const auto& [camera_id, c0] : camera_col) {
    const Camera& camera = rec.cameras.at(camera_id);
    const Eigen::MatrixXd directions = IntrinsicDirections(camera, free.at(camera_id));
    for (int j = 0; j < directions.cols(); ++j) {
      const double var = cov(k, k);
      const double sd = var > 0.0 ? std::sqrt(var) : std::numeric_limits<double>::infinity();
      out.stddev.push_back(sd);
      out.stddev_px.push_back(sd * CornerPixelSensitivity(camera, directions.col(j)));
      out.max_stddev_px = std::max(out.max_stddev_px, out.stddev_px.back());
      double& camera_max = out.camera_max_stddev_px[camera_id];
      camera_max = std::max(camera_max, out.stddev_px.back());
      ++k;
    }
  }
  if (!std::isfinite(out.max_stddev_px)) out.ok = false;
  return out;
}

}  // namespace pgba
