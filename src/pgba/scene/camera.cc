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
  const double* p = params.data();
  Eigen::Vector2d d;  // distorted normalised coordinates
  if (HasSeparateFocals(model)) {
    d << (pixel.x() - p[2]) / p[0], (pixel.y() - p[3]) / p[1];
  } else {
    d << (pixel.x() - p[1]) / p[0], (pixel.y() - p[2]) / p[0];
  }
  if (model == CameraModel::kSimplePinhole || model == CameraModel::kPinhole) return d;
  // Newton on distort(u) = d with an autodiff 2x2 Jacobian. Distortion is a small
  // perturbation of identity over the image, so starting from u = d converges in a few steps.
  using Jet = ceres::Jet<double, 2>;
  Eigen::Vector2d u = d;
  for (int it = 0; it < 50; ++it) {
    Jet ju(u.x(), 0), jv(u.y(), 1), jud, jvd;
    DistortNormalized(model, p, ju, jv, &jud, &jvd);
    Eigen::Vector2d r(jud.a - d.x(), jvd.a - d.y());
    Eigen::Matrix2d J;
    J << jud.v[0], jud.v[1], jvd.v[0], jvd.v[1];
    const Eigen::Vector2d step = J.partialPivLu().solve(r);
    if (!step.allFinite()) break;
    u -= step;
    if (step.squaredNorm() < 1e-30) break;
  }
  return u;
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
  return "";
}

}  // namespace pgba
