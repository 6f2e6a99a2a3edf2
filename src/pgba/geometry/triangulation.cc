#include "pgba/geometry/triangulation.h"

#include <ceres/jet.h>

#include <Eigen/Dense>
#include <cmath>

#include "pgba/geometry/rotation.h"

namespace pgba {

bool TriangulateLinear(const std::vector<Pose>& poses, const std::vector<Eigen::Vector3d>& bearings,
                       Eigen::Vector3d* X) {
  const int n = static_cast<int>(poses.size());
  if (n < 2) return false;
  Eigen::MatrixXd A(3 * n, 4);
  for (int i = 0; i < n; ++i) {
    Eigen::Matrix<double, 3, 4> P;
    P.leftCols<3>() = poses[i].R();
    P.col(3) = poses[i].t();
    A.middleRows<3>(3 * i) = Skew(bearings[i]) * P;
  }
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(A, Eigen::ComputeFullV);
  const Eigen::Vector4d h = svd.matrixV().col(3);
  if (std::abs(h(3)) < 1e-12 * h.head<3>().norm()) return false;
  *X = h.head<3>() / h(3);
  return X->allFinite();
}

namespace {

// Pixel residual of view v at X and its 2x3 Jacobian (autodiff through the camera model).
bool Residual(const TrackView& v, const Eigen::Vector3d& X, Eigen::Vector2d* r, Eigen::Matrix<double, 2, 3>* J) {
  using Jet = ceres::Jet<double, 3>;
  const Eigen::Vector3d xc = v.pose.ToCamera(X);
  if (!(xc.z() > 1e-12 * xc.norm())) return false;
  const Eigen::Matrix3d R = v.pose.R();
  Jet xcj[3];
  for (int k = 0; k < 3; ++k) {
    xcj[k].a = xc(k);
    xcj[k].v = R.row(k).transpose();
  }
  Jet px[2];
  ProjectToPixel(v.camera->model, v.camera->params.data(), xcj, px);
  for (int k = 0; k < 2; ++k) {
    (*r)(k) = px[k].a - v.pixel(k);
    J->row(k) = px[k].v.transpose();
  }
  return r->allFinite();
}

// Huber-IRLS Gauss-Newton; returns false if a view ends behind its camera.
bool RefineGaussNewton(const std::vector<TrackView>& views, const TriangulationOptions& opt, Eigen::Vector3d* X) {
  for (int it = 0; it < opt.max_iterations; ++it) {
    Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
    Eigen::Vector3d g = Eigen::Vector3d::Zero();
    for (const auto& v : views) {
      Eigen::Vector2d r;
      Eigen::Matrix<double, 2, 3> J;
      if (!Residual(v, *X, &r, &J)) return false;
      const double e = r.norm();
      const double w = e <= opt.huber_px ? 1.0 : opt.huber_px / e;
      H += w * J.transpose() * J;
      g += w * J.transpose() * r;
    }
    const Eigen::Vector3d dx = H.ldlt().solve(-g);
    if (!dx.allFinite()) return false;
    *X += dx;
    if (dx.norm() < 1e-10 * (1.0 + X->norm())) break;
  }
  return true;
}

std::vector<double> Residuals(const std::vector<TrackView>& views, const Eigen::Vector3d& X, bool* in_front) {
  std::vector<double> res(views.size());
  *in_front = true;
  for (size_t i = 0; i < views.size(); ++i) {
    const Eigen::Vector3d xc = views[i].pose.ToCamera(X);
    if (!(xc.z() > 0)) *in_front = false;
    res[i] = xc.z() > 0 ? (views[i].camera->Project(xc) - views[i].pixel).norm() : 1e30;
  }
  return res;
}

size_t CountInliers(const std::vector<double>& res, double thr) {
  size_t n = 0;
  for (double r : res) n += r < thr;
  return n;
}

bool LinearFrom(const std::vector<TrackView>& views, const std::vector<size_t>& idx, Eigen::Vector3d* X) {
  std::vector<Pose> poses;
  std::vector<Eigen::Vector3d> bearings;
  for (size_t i : idx) {
    poses.push_back(views[i].pose);
    bearings.push_back(views[i].camera->PixelToBearing(views[i].pixel));
  }
  return TriangulateLinear(poses, bearings, X);
}

}  // namespace

double MaxTriangulationAngleDeg(const std::vector<TrackView>& views, const Eigen::Vector3d& X) {
  double best = 0.0;
  for (size_t i = 0; i < views.size(); ++i) {
    const Eigen::Vector3d a = (X - views[i].pose.C()).normalized();
    for (size_t j = i + 1; j < views.size(); ++j) {
      const Eigen::Vector3d b = (X - views[j].pose.C()).normalized();
      best = std::max(best, std::atan2(a.cross(b).norm(), a.dot(b)));
    }
  }
  return best * 180.0 / M_PI;
}

TriangulatedPoint TriangulateTrack(const std::vector<TrackView>& views, const TriangulationOptions& opt) {
  TriangulatedPoint out;
  const size_t n = views.size();
  if (n < 2) return out;
  std::vector<size_t> all(n);
  for (size_t i = 0; i < n; ++i) all[i] = i;

  Eigen::Vector3d X;
  bool in_front = false;
  std::vector<double> res;
  bool have = LinearFrom(views, all, &X) && RefineGaussNewton(views, opt, &X);
  if (have) res = Residuals(views, X, &in_front);
  // Consensus restart: an outlier observation pulls the linear solution; try every pair
  // (tracks are short) and keep the one with most inliers, then refine on all views.
  if (n >= 3 && (!have || !in_front || CountInliers(res, opt.outlier_px) < n)) {
    size_t best_inl = have && in_front ? CountInliers(res, opt.outlier_px) : 0;
    Eigen::Vector3d best_X = X;
    for (size_t i = 0; i < n && n <= 64; ++i) {
      for (size_t j = i + 1; j < n; ++j) {
        Eigen::Vector3d Y;
        if (!LinearFrom(views, {i, j}, &Y)) continue;
        bool front;
        const std::vector<double> r = Residuals(views, Y, &front);
        const size_t inl = CountInliers(r, opt.outlier_px);
        if (inl > best_inl) {
          best_inl = inl;
          best_X = Y;
        }
      }
    }
    if (best_inl >= 2) {
      X = best_X;
      have = RefineGaussNewton(views, opt, &X);
      if (have) res = Residuals(views, X, &in_front);
    }
  }
  if (!have) return out;
  // Every inlier view must see the point in front; outlier views may be behind.
  for (size_t i = 0; i < n; ++i)
    if (res[i] < opt.outlier_px && !(views[i].pose.ToCamera(X).z() > 0)) return out;
  if (CountInliers(res, 1e29) < 2) return out;
  out.max_angle_deg = MaxTriangulationAngleDeg(views, X);
  if (out.max_angle_deg < opt.min_angle_deg) return out;
  out.ok = true;
  out.X = X;
  out.residuals_px = std::move(res);
  return out;
}

}  // namespace pgba
