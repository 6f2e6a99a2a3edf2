#include "pgba/scene/camera.h"

#include <ceres/jet.h>

#include <Eigen/LU>

#include <cmath>

namespace pgba {
namespace {
struct ModelInfo {
  CameraModel model;
  const char* name;
  int num_params;
};
constexpr ModelInfo kModels[] = {{CameraModel::kSimplePinhole, "SIMPLE_PINHOLE", 3},
                                 {CameraModel::kPinhole, "PINHOLE", 4},
                                 {CameraModel::kSimpleRadial, "SIMPLE_RADIAL", 4},
                                 {CameraModel::kRadial, "RADIAL", 5},
                                 {CameraModel::kOpenCV, "OPENCV", 8}};

bool HasSeparateFocals(CameraModel m) { return m == CameraModel::kPinhole || m == CameraModel::kOpenCV; }

// Determinant of the Jacobian of distort() at normalised coordinates u: > 0 where the
// distortion keeps orientation, <= 0 where it folds.
double DistortionJacobianDeterminant(CameraModel model, const double* p, const Eigen::Vector2d& u) {
  using Jet = ceres::Jet<double, 2>;
  Jet ju(u.x(), 0), jv(u.y(), 1), jud, jvd;
  DistortNormalized(model, p, ju, jv, &jud, &jvd);
  return jud.v[0] * jvd.v[1] - jud.v[1] * jvd.v[0];
}
}  // namespace

const char* CameraModelName(CameraModel model) { return kModels[static_cast<int>(model)].name; }

bool ParseCameraModel(const std::string& name, CameraModel* model) {
  for (const auto& m : kModels) {
    if (name == m.name) {
      *model = m.model;
      return true;
    }
  }
  return false;
}

int CameraModelNumParams(CameraModel model) { return kModels[static_cast<int>(model)].num_params; }

Eigen::Vector2d Camera::Project(const Eigen::Vector3d& x_cam) const {
  Eigen::Vector2d px;
  ProjectToPixel(model, params.data(), x_cam.data(), px.data());
  return px;
}

Eigen::Vector2d Camera::PixelToNormalized(const Eigen::Vector2d& pixel) const {
  Eigen::Vector2d u;
  UndistortPixel(pixel, &u);
  return u;
}

bool Camera::UndistortPixel(const Eigen::Vector2d& pixel, Eigen::Vector2d* normalized) const {
  const double* p = params.data();
  Eigen::Vector2d d;  // distorted normalised coordinates
  if (HasSeparateFocals(model)) {
    d << (pixel.x() - p[2]) / p[0], (pixel.y() - p[3]) / p[1];
  } else {
    d << (pixel.x() - p[1]) / p[0], (pixel.y() - p[2]) / p[0];
  }
  *normalized = d;
  if (model == CameraModel::kSimplePinhole || model == CameraModel::kPinhole) return d.allFinite();
  // Newton on distort(u) = d with an autodiff 2x2 Jacobian. Distortion is a small
  // perturbation of identity over the image, so starting from u = d converges in a few steps.
  using Jet = ceres::Jet<double, 2>;
  Eigen::Vector2d& u = *normalized;
  bool converged = false;
  for (int it = 0; it < 50 && !converged; ++it) {
    Jet ju(u.x(), 0), jv(u.y(), 1), jud, jvd;
    DistortNormalized(model, p, ju, jv, &jud, &jvd);
    const Eigen::Vector2d r(jud.a - d.x(), jvd.a - d.y());
    Eigen::Matrix2d J;
    J << jud.v[0], jud.v[1], jvd.v[0], jvd.v[1];
    const Eigen::Vector2d step = J.partialPivLu().solve(r);
    if (!step.allFinite()) return false;
    u -= step;
    converged = step.squaredNorm() < 1e-30;
  }
  if (!converged) {  // steps that never shrink below 1e-15 may still sit on the root
    double ud, vd;
    DistortNormalized(model, p, u.x(), u.y(), &ud, &vd);
    converged = (Eigen::Vector2d(ud, vd) - d).squaredNorm() < 1e-20;
  }
  // A root on the folded side of the distortion is not the pixel's ray, nor is one across
  // the centre (a barrel polynomial r (1 + k r^2) with k << 0 maps -r to +r' beyond its fold,
  // where the determinant is positive again).
  return converged && u.dot(d) >= 0.0 && DistortionJacobianDeterminant(model, p, u) > 0.0;
}

Eigen::Vector3d Camera::PixelToBearing(const Eigen::Vector2d& pixel) const {
  const Eigen::Vector2d n = PixelToNormalized(pixel);
  return Eigen::Vector3d(n.x(), n.y(), 1.0).normalized();
}

double Camera::MeanFocal() const {
  if (params.empty()) return 0.0;
  return HasSeparateFocals(model) ? 0.5 * (params[0] + params[1]) : params[0];
}

std::string Camera::Validate() const {
  if (static_cast<int>(params.size()) != CameraModelNumParams(model))
    return std::string(CameraModelName(model)) + " needs " + std::to_string(CameraModelNumParams(model)) +
           " parameters, got " + std::to_string(params.size());
  for (double v : params)
    if (!std::isfinite(v)) return "non-finite camera parameter";
  if (width <= 0 || height <= 0) return "image size must be positive";
  if (!(params[0] > 0) || (HasSeparateFocals(model) && !(params[1] > 0))) return "focal length must be positive";
  // A 9 x 9 grid from corner to corner (the extreme radii are at the corners). For
  // SIMPLE_RADIAL k = -40 on a normal lens, the distorted radius of the corners is beyond
  // the largest that distort() reaches: no ray maps there, the calibration is wrong.
  constexpr int kGrid = 8;
  for (int i = 0; i <= kGrid; ++i) {
    for (int j = 0; j <= kGrid; ++j) {
      const Eigen::Vector2d pixel(width * double(i) / kGrid, height * double(j) / kGrid);
      Eigen::Vector2d u;
      // The ray must also be reached without a fold on the way from the centre: a
      // polynomial that turns round and back up (OPENCV k1 = -3, k2 = 0.04) has a root far
      // out with a positive determinant, but the pixels between the folds have two rays.
      bool unfolded = UndistortPixel(pixel, &u);
      for (int t = 1; unfolded && t < 16; ++t)
        unfolded = DistortionJacobianDeterminant(model, params.data(), u * (t / 16.0)) > 0.0;
      if (!unfolded)
        return "distortion is not invertible over the image (no undistorted ray for pixel (" +
               std::to_string(static_cast<int>(pixel.x())) + ", " + std::to_string(static_cast<int>(pixel.y())) +
               ")): check the distortion coefficients";
    }
  }
  return "";
}

}  // namespace pgba
