#include "pgba/geometry/sim3.h"

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <cmath>

#include "pgba/geometry/rotation.h"

namespace pgba {

Pose Sim3::Apply(const Pose& pose) const { return Pose::FromRC(pose.R() * R.transpose(), Apply(pose.C())); }

Sim3 Sim3::Inverse() const {
  Sim3 inv;
  inv.s = 1.0 / s;
  inv.R = R.transpose();
  inv.t = -inv.s * (inv.R * t);
  return inv;
}

Sim3 Sim3::operator*(const Sim3& b) const {
  Sim3 c;
  c.s = s * b.s;
  c.R = R * b.R;
  c.t = s * (R * b.t) + t;
  return c;
}

Eigen::Matrix4d Sim3::Matrix() const {
  Eigen::Matrix4d M = Eigen::Matrix4d::Identity();
  M.topLeftCorner<3, 3>() = s * R;
  M.topRightCorner<3, 1>() = t;
  return M;
}

bool EstimateSim3(const std::vector<Eigen::Vector3d>& src, const std::vector<Eigen::Vector3d>& dst,
                  Sim3* sim) {
  const int n = static_cast<int>(src.size());
  if (n < 3 || dst.size() != src.size()) return false;
  Eigen::Matrix3Xd A(3, n), B(3, n);
  for (int i = 0; i < n; ++i) {
    A.col(i) = src[i];
    B.col(i) = dst[i];
  }
  // Degeneracy: the centred source points must span at least a line with spread in a second
  // direction (collinear points leave the rotation about that line free).
  const Eigen::Matrix3Xd Ac = A.colwise() - A.rowwise().mean();
  Eigen::JacobiSVD<Eigen::Matrix3Xd> svd(Ac);
  const Eigen::Vector3d sv = svd.singularValues();
  if (!(sv(0) > 0) || sv(1) < 1e-9 * sv(0)) return false;
  const Eigen::Matrix4d T = Eigen::umeyama(A, B, true);
  if (!T.allFinite()) return false;
  const Eigen::Matrix3d sR = T.topLeftCorner<3, 3>();
  sim->s = std::cbrt(sR.determinant());
  if (!(sim->s > 0)) return false;
  sim->R = sR / sim->s;
  sim->t = T.topRightCorner<3, 1>();
  return true;
}

Eigen::Vector3d MeanCentre(const std::vector<Pose>& poses) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const Pose& p : poses) sum += p.C();
  return poses.empty() ? sum : Eigen::Vector3d(sum / static_cast<double>(poses.size()));
}

Eigen::Matrix3d MotionRotation(const std::vector<Eigen::Matrix3d>& global_R, const std::vector<Eigen::Matrix3d>& local_R) {
  Eigen::Matrix3d sum = Eigen::Matrix3d::Zero();
  for (size_t k = 0; k < global_R.size(); ++k) sum += local_R[k].transpose() * global_R[k];
  return ClosestRotation(sum);
}

bool MotionSimilarityFit::scale_ok() const { return lambda > 0.0 && std::isfinite(lambda); }

Sim3 MotionSimilarityFit::ToSim3() const {
  Sim3 sim;
  sim.s = lambda;
  sim.R = alpha;
  sim.t = local_centroid - lambda * (alpha * global_centroid);
  return sim;
}

MotionSimilarityFit FitMotionSimilarity(const std::vector<Pose>& global, const std::vector<Pose>& local) {
  MotionSimilarityFit fit;
  std::vector<Eigen::Matrix3d> global_R, local_R;
  for (size_t k = 0; k < global.size(); ++k) {
    global_R.push_back(global[k].R());
    local_R.push_back(local[k].R());
  }
  fit.alpha = MotionRotation(global_R, local_R);
  fit.global_centroid = MeanCentre(global);
  fit.local_centroid = MeanCentre(local);
  double num = 0.0, den = 0.0;
  for (size_t k = 0; k < global.size(); ++k) {
    const Eigen::Vector3d d = fit.alpha * (global[k].C() - fit.global_centroid);
    num += (local[k].C() - fit.local_centroid).dot(d);
    den += d.squaredNorm();
  }
  fit.lambda = den > 0.0 ? num / den : 0.0;
  return fit;
}

}  // namespace pgba
