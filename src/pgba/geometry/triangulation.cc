#include "pgba/geometry/triangulation.h"
#include "pgba/io/option_ranges.h"

#include <ceres/jet.h>

#include <Eigen/Dense>  // SelfAdjointEigenSolver
#include <algorithm>
#include <cmath>
#include <limits>

namespace pgba {

namespace {

// The linear triangulation's normal matrix over the views `idx` (Hartley & Zisserman 12.2,
// DLT): A^T A = sum_i P_i^T [b_i]_x^T [b_i]_x P_i with P_i = [R_i | t_i], accumulated as 4x4
// (for a unit bearing [b]_x^T [b]_x = I - b b^T). Its eigenvector of the smallest eigenvalue
// is the null vector of A. Why not an SVD of the 3n x 4 A: the triangulation of every track
// runs in every pass over the observations (local Hessians, re-linearisation, the final
// model), and a dynamic-size Jacobi SVD per track was 40% of it; the 4x4 eigen solve is fixed
// size, allocates nothing, and its start is refined by Gauss-Newton on the pixels anyway.
// A^T A squares A's condition number, so the cameras are first normalised (Hartley): centres
// relative to their mean c, in units of their RMS distance d from it, X = c + d X'; with
// that, georeferenced coordinates (1e6 m) lose nothing.
template <typename PoseAt, typename BearingAt>
bool SolveNormalMatrix(size_t n, const PoseAt& pose_at, const BearingAt& bearing_at, Eigen::Vector3d* X) {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < n; ++i) c += pose_at(i).C();
  c /= static_cast<double>(n);
  double d2 = 0.0;
  for (size_t i = 0; i < n; ++i) d2 += (pose_at(i).C() - c).squaredNorm();
  const double d = d2 > 0 ? std::sqrt(d2 / n) : 1.0;
  Eigen::Matrix4d M = Eigen::Matrix4d::Zero();
  for (size_t i = 0; i < n; ++i) {
    const Pose& pose = pose_at(i);
    const Eigen::Vector3d b = bearing_at(i).normalized();
    Eigen::Matrix<double, 3, 4> P;  // R (c + d X' - C) = d [R | R (c - C) / d] [X'; 1]
    P.leftCols<3>() = pose.R();
    P.col(3) = pose.R() * ((c - pose.C()) / d);
    const Eigen::Matrix<double, 3, 4> Q = P - b * (b.transpose() * P);  // (I - b b^T) P
    M.noalias() += P.transpose() * Q;  // P^T (I - b b^T) P: (I - b b^T) is idempotent
  }
  if (!M.allFinite()) return false;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> eig(M);
  if (eig.info() != Eigen::Success) return false;
  const Eigen::Vector4d h = eig.eigenvectors().col(0);  // eigenvalues ascending
  if (!(std::abs(h(3)) >= 1e-12 * h.head<3>().norm())) return false;
  *X = c + d * (h.head<3>() / h(3));
  return X->allFinite();
}

}  // namespace

bool TriangulateLinear(const std::vector<Pose>& poses, const std::vector<Eigen::Vector3d>& bearings,
                       Eigen::Vector3d* X) {
  if (poses.size() < 2 || bearings.size() != poses.size()) return false;
  return SolveNormalMatrix(
      poses.size(), [&](size_t i) -> const Pose& { return poses[i]; },
      [&](size_t i) -> const Eigen::Vector3d& { return bearings[i]; }, X);
}

namespace {

constexpr double kBehind = 1e30;  // residual reported for a view that sees the point behind it

// Pixel residual of view v at X and its 2x3 Jacobian (autodiff through the camera model;
// in closed form for the models without distortion, in the same operations as the Jet's
// quotient rule, so the same bits). False if X is not in front of the camera.
bool Residual(const TrackView& v, const Eigen::Vector3d& X, Eigen::Vector2d* r, Eigen::Matrix<double, 2, 3>* J) {
  using Jet = ceres::Jet<double, 3>;
  const Eigen::Vector3d xc = v.pose.ToCamera(X);
  if (!(xc.z() > 1e-12 * xc.norm())) return false;
  const Eigen::Matrix3d R = v.pose.R();
  const CameraModel model = v.camera->model;
  if (model == CameraModel::kPinhole || model == CameraModel::kSimplePinhole) {
    // pixel = f (x / z) + c; d(x / z) / dX = (R_0 - (x / z) R_2) / z.
    const double* p = v.camera->params.data();
    const bool simple = model == CameraModel::kSimplePinhole;
    const double f[2] = {p[0], simple ? p[0] : p[1]};
    const double c[2] = {simple ? p[1] : p[2], simple ? p[2] : p[3]};
    const double inverse_z = 1.0 / xc.z();
    for (int k = 0; k < 2; ++k) {
      const double u = xc(k) * inverse_z;
      (*r)(k) = (f[k] * u + c[k]) - v.pixel(k);
      J->row(k) = f[k] * ((R.row(k) - u * R.row(2)) * inverse_z);
    }
    return r->allFinite() && J->allFinite();
  }
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
  return r->allFinite() && J->allFinite();
}

// Reprojection error of view v at X (kBehind if it sees X behind it).
double ResidualPx(const TrackView& v, const Eigen::Vector3d& X) {
  const Eigen::Vector3d xc = v.pose.ToCamera(X);
  const double r = xc.z() > 0 ? (v.camera->Project(xc) - v.pixel).norm() : kBehind;
  return std::isfinite(r) ? r : kBehind;
}

// Reprojection error of every view.
std::vector<double> Residuals(const std::vector<TrackView>& views, const Eigen::Vector3d& X) {
  std::vector<double> res(views.size());
  for (size_t i = 0; i < views.size(); ++i) res[i] = ResidualPx(views[i], X);
  return res;
}

double Huber(double e, double k) { return e <= k ? e * e : 2.0 * k * e - k * k; }

// Huber cost over the views in `use`; infinite if one of them sees X behind it.
double HuberCost(const std::vector<TrackView>& views, const std::vector<size_t>& use, const Eigen::Vector3d& X,
                 double k) {
  double cost = 0.0;
  for (size_t i : use) {
    const Eigen::Vector3d xc = views[i].pose.ToCamera(X);
    if (!(xc.z() > 1e-12 * xc.norm())) return std::numeric_limits<double>::infinity();
    cost += Huber((views[i].camera->Project(xc) - views[i].pixel).norm(), k);
  }
  return std::isfinite(cost) ? cost : std::numeric_limits<double>::infinity();
}

// The Huber-IRLS normal equations of the views in `use` at X and their Huber cost (the same
// sum as HuberCost); false if X is behind one of them.
bool LinearizeHuber(const std::vector<TrackView>& views, const std::vector<size_t>& use, const Eigen::Vector3d& X,
                    double k, Eigen::Matrix3d* H, Eigen::Vector3d* g, double* cost) {
  H->setZero();
  g->setZero();
  *cost = 0.0;
  for (size_t i : use) {
    Eigen::Vector2d r;
    Eigen::Matrix<double, 2, 3> J;
    if (!Residual(views[i], X, &r, &J)) return false;
    const double e = r.norm();
    const double w = e <= k ? 1.0 : k / e;
    *H += w * J.transpose() * J;
    *g += w * J.transpose() * r;
    *cost += Huber(e, k);
  }
  return std::isfinite(*cost);
}

// Huber-IRLS Gauss-Newton over the views in `use`, with step halving so that the cost never
// increases and no used view ends behind its camera. False if X starts behind a used view.
// The full step is tried by linearising at it (its cost comes with the next normal
// equations, one projection pass per iteration instead of two); a refused one is halved.
bool RefineGaussNewton(const std::vector<TrackView>& views, const std::vector<size_t>& use,
                       const TriangulationOptions& opt, Eigen::Vector3d* X) {
  const double k = opt.huber_px;
  Eigen::Matrix3d H;
  Eigen::Vector3d g;
  double cost;
  if (!LinearizeHuber(views, use, *X, k, &H, &g, &cost)) return false;
  for (int it = 0; it < opt.max_iterations; ++it) {
    Eigen::Vector3d dx = H.ldlt().solve(-g);
    if (!dx.allFinite()) break;
    bool improved = false;
    Eigen::Matrix3d H_full;
    Eigen::Vector3d g_full;
    double c_full;
    const Eigen::Vector3d full = *X + dx;
    if (LinearizeHuber(views, use, full, k, &H_full, &g_full, &c_full) && c_full <= cost) {
      improved = true;
      *X = full;
      cost = c_full;
      H = H_full;
      g = g_full;
      dx *= 0.5;  // as the halving loop leaves it: the stop test below sees half the step
    } else {
      dx *= 0.5;
      for (int halving = 1; halving < 20 && !improved; ++halving, dx *= 0.5) {
        const Eigen::Vector3d Y = *X + dx;
        const double c = HuberCost(views, use, Y, k);
        if (c <= cost) {
          improved = true;
          *X = Y;
          cost = c;
        }
      }
      if (improved && !LinearizeHuber(views, use, *X, k, &H, &g, &cost)) break;
    }
    // Converged when the step is below 1e-9 of the point's scale: ~1e-6 px at a focal of
    // 1000 px. A tighter test (1e-12) sat at the rounding level of the cost, so 6% of the
    // tracks ran all max_iterations in steps that no longer changed it.
    if (!improved || dx.norm() < 1e-9 * (1.0 + X->norm())) break;
  }
  return true;
}

// The linear solution over the `count` views idx[0..count-1] (a pointer, not a vector: the
// consensus search below calls it for every pair of views).
bool LinearFrom(const std::vector<TrackView>& views, const std::vector<Eigen::Vector3d>& bearings,
                const size_t* idx, size_t count, Eigen::Vector3d* X) {
  if (count < 2) return false;
  return SolveNormalMatrix(
      count, [&](size_t i) -> const Pose& { return views[idx[i]].pose; },
      [&](size_t i) -> const Eigen::Vector3d& { return bearings[idx[i]]; }, X);
}

std::vector<size_t> Below(const std::vector<double>& res, double thr) {
  std::vector<size_t> idx;
  for (size_t i = 0; i < res.size(); ++i)
    if (res[i] < thr) idx.push_back(i);
  return idx;
}

// A solution and how well the views support it: more inliers first, then the smaller
// truncated cost sum min(r, outlier_px)^2 (outliers count as a constant).
struct Candidate {
  bool ok = false;
  Eigen::Vector3d X = Eigen::Vector3d::Zero();
  std::vector<double> res;
  size_t inliers = 0;
  double cost = std::numeric_limits<double>::infinity();
};

Candidate Score(const std::vector<TrackView>& views, const Eigen::Vector3d& X, double outlier_px) {
  Candidate c;
  c.X = X;
  c.res = Residuals(views, X);
  c.cost = 0.0;
  for (double r : c.res) {
    c.inliers += r < outlier_px;
    c.cost += std::min(r, outlier_px) * std::min(r, outlier_px);
  }
  c.ok = Below(c.res, kBehind).size() >= 2;
  return c;
}

bool Better(const Candidate& a, const Candidate& b) {
  if (a.ok != b.ok) return a.ok;
  if (a.inliers != b.inliers) return a.inliers > b.inliers;
  return a.cost < b.cost;
}

// Whether X scores Better than `best` (Score then Better, without storing the residuals):
// stops as soon as X can no longer reach best's inlier count. The consensus search scores
// every pair of views of a track that holds an outlier, O(n^3) projections per track, most
// of them for candidates that lose.
bool ScoresBetter(const std::vector<TrackView>& views, const Eigen::Vector3d& X, double outlier_px,
                  const Candidate& best) {
  size_t inliers = 0, in_front = 0;
  double cost = 0.0;
  const size_t n = views.size();
  for (size_t i = 0; i < n; ++i) {
    const double r = ResidualPx(views[i], X);
    inliers += r < outlier_px;
    in_front += r < kBehind;
    cost += std::min(r, outlier_px) * std::min(r, outlier_px);
    // best.ok: a candidate needs more inliers, or as many and a lower cost; the cost only grows.
    if (best.ok && inliers + (n - 1 - i) < best.inliers) return false;
  }
  Candidate c;
  c.ok = in_front >= 2;
  c.inliers = inliers;
  c.cost = cost;
  return Better(c, best);
}

// Robust refinement from a starting point: Huber Gauss-Newton on the views that agree with
// the start (r < outlier_px), then again on the inliers of the result until the inlier set
// is stable, so that an outlier does not bias the point (Huber alone still pulls it by
// ~huber_px / #inliers). Where fewer than two views agree (e.g. poor initial poses), all
// views in front are used with the Huber loss: the caller still gets the best point those
// poses allow.
Candidate RobustRefine(const std::vector<TrackView>& views, const Eigen::Vector3d& start,
                       const TriangulationOptions& opt) {
  const std::vector<double> res0 = Residuals(views, start);
  std::vector<size_t> used = Below(res0, opt.outlier_px);
  if (used.size() < 2) used = Below(res0, kBehind);
  Eigen::Vector3d X = start;
  if (used.size() < 2 || !RefineGaussNewton(views, used, opt, &X)) return Candidate();
  Candidate best = Score(views, X, opt.outlier_px);
  for (int round = 0; round < 10; ++round) {
    const std::vector<size_t> inl = Below(best.res, opt.outlier_px);
    if (inl.size() < 2 || inl == used) break;
    Eigen::Vector3d Y = best.X;
    if (!RefineGaussNewton(views, inl, opt, &Y)) break;
    used = inl;
    best = Score(views, Y, opt.outlier_px);
  }
  return best;
}

// The point of `best` if it is one (in front of two views) and its supporting views see it
// under at least min_angle_deg.
TriangulatedPoint Accepted(const std::vector<TrackView>& views, Candidate best, const TriangulationOptions& opt) {
  TriangulatedPoint out;
  if (!best.ok) return out;
  // The angle that makes depth observable is the one between views that support the point.
  std::vector<TrackView> support;
  const std::vector<size_t> inl = Below(best.res, opt.outlier_px);
  for (size_t i : (inl.size() >= 2 ? inl : Below(best.res, kBehind))) support.push_back(views[i]);
  out.max_angle_deg = MaxTriangulationAngleDeg(support, best.X);
  if (out.max_angle_deg < opt.min_angle_deg) return out;
  out.ok = true;
  out.X = best.X;
  out.residuals_px = std::move(best.res);
  return out;
}

}  // namespace

double MaxTriangulationAngleDeg(const std::vector<TrackView>& views, const Eigen::Vector3d& X) {
  // The widest pair is the one whose unit rays have the smallest dot product; its angle is
  // then taken with atan2, accurate at small angles where acos of the dot product is not.
  std::vector<Eigen::Vector3d> rays(views.size());
  for (size_t i = 0; i < views.size(); ++i) rays[i] = (X - views[i].pose.C()).normalized();
  double lowest = std::numeric_limits<double>::infinity();
  size_t a = 0, b = 0;
  for (size_t i = 0; i < rays.size(); ++i)
    for (size_t j = i + 1; j < rays.size(); ++j) {
      const double d = rays[i].dot(rays[j]);
      if (d < lowest) {
        lowest = d;
        a = i;
        b = j;
      }
    }
  if (a == b) return 0.0;
  return std::max(0.0, std::atan2(rays[a].cross(rays[b]).norm(), rays[a].dot(rays[b]))) * 180.0 / M_PI;
}

TriangulatedPoint TriangulateTrack(const std::vector<TrackView>& views, const TriangulationOptions& opt) {
  TriangulatedPoint out;
  const size_t n = views.size();
  if (n < 2) return out;
  std::vector<size_t> all(n);
  for (size_t i = 0; i < n; ++i) all[i] = i;

  std::vector<Eigen::Vector3d> bearings(n);
  for (size_t i = 0; i < n; ++i) bearings[i] = views[i].camera->PixelToBearing(views[i].pixel);

  Candidate best;
  Eigen::Vector3d X;
  if (LinearFrom(views, bearings, all.data(), all.size(), &X)) best = RobustRefine(views, X, opt);
  // Consensus restart: an outlier observation pulls the linear solution (or puts it behind
  // a camera); start again from the two-view solution that most views agree with. Tracks
  // are short; for long ones the pairs are drawn from 32 evenly spread views (496 pairs).
  if (n >= 3 && (!best.ok || best.inliers < n)) {
    std::vector<size_t> pick;
    const size_t m = std::min<size_t>(n, 32);
    for (size_t k = 0; k < m; ++k) pick.push_back(k * n / m);
    Candidate start;
    for (size_t a = 0; a < m; ++a) {
      for (size_t b = a + 1; b < m; ++b) {
        Eigen::Vector3d Y;
        const size_t pair[2] = {pick[a], pick[b]};
        if (!LinearFrom(views, bearings, pair, 2, &Y)) continue;
        if (ScoresBetter(views, Y, opt.outlier_px, start)) start = Score(views, Y, opt.outlier_px);
      }
    }
    if (start.ok) {
      const Candidate c = RobustRefine(views, start.X, opt);
      if (Better(c, best)) best = c;
    }
  }
  return Accepted(views, std::move(best), opt);
}

TriangulatedPoint TriangulateTrackFrom(const std::vector<TrackView>& views, const PointStart& start,
                                       const TriangulationOptions& opt) {
  if (views.size() < 2 || !start.X.allFinite() || start.support < 2) return TriangulateTrack(views, opt);
  Candidate best = RobustRefine(views, start.X, opt);
  if (!best.ok || best.inliers < static_cast<size_t>(start.support)) return TriangulateTrack(views, opt);
  return Accepted(views, std::move(best), opt);
}

std::string TriangulationOptions::Check() const {
  return CheckRangesAt({{"huber_px", huber_px}, {"outlier_px", outlier_px}, {"max_iterations", max_iterations},
                       {"min_angle_deg", min_angle_deg}},
                      "TriangulationOptions");
}

}  // namespace pgba
