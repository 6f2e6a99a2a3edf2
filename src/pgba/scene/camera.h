// COLMAP camera models: projection of camera-frame points to pixels and the inverse,
// pixels to unit bearing vectors (undistortion).
//
// Parameter layouts are COLMAP's (cameras.txt):
//   SIMPLE_PINHOLE  f, cx, cy
//   PINHOLE         fx, fy, cx, cy
//   SIMPLE_RADIAL   f, cx, cy, k
//   RADIAL          f, cx, cy, k1, k2
//   OPENCV          fx, fy, cx, cy, k1, k2, p1, p2
// Projection is templated so that Ceres cost functions (autodiff Jets) and plain doubles
// share one implementation.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

namespace pgba {

enum class CameraModel { kSimplePinhole = 0, kPinhole = 1, kSimpleRadial = 2, kRadial = 3, kOpenCV = 4 };

// Name <-> model ("PINHOLE" ...). ParseCameraModel returns false for unknown names.
const char* CameraModelName(CameraModel model);
bool ParseCameraModel(const std::string& name, CameraModel* model);
int CameraModelNumParams(CameraModel model);

struct Camera {
  uint32_t camera_id = 0;
  CameraModel model = CameraModel::kPinhole;
  int width = 0;
  int height = 0;
  std::vector<double> params;
  // COLMAP's flag of the same name: true when the focal comes from a calibration file or
  // EXIF, false when it is only the 1.2 * max(width, height) guess (image_catalog.h). The
  // global mapper estimates the focal of the cameras without one from the view graph
  // (modules/calibration). cameras.txt carries it in a comment COLMAP ignores
  // (colmap_text.h); a camera of a calibration file without that comment has a prior.
  bool has_prior_focal_length = true;

  // Pixels of a point in the camera frame (z > 0 expected; no check here).
  Eigen::Vector2d Project(const Eigen::Vector3d& x_cam) const;
  // Normalised, undistorted image coordinates (x/z, y/z) of a pixel. For a calibration that
  // passed Validate() the undistortion converges over the whole image; otherwise this is
  // the last Newton iterate (see UndistortPixel).
  Eigen::Vector2d PixelToNormalized(const Eigen::Vector2d& pixel) const;
  // The same, reporting failure: false when the Newton iteration on distort(u) = d does not
  // converge, or converges where the distortion folds back (Jacobian determinant <= 0:
  // beyond the radius where a barrel distortion turns round, distort is not invertible).
  bool UndistortPixel(const Eigen::Vector2d& pixel, Eigen::Vector2d* normalized) const;
  // Unit bearing vector (camera frame) of a pixel.
  Eigen::Vector3d PixelToBearing(const Eigen::Vector2d& pixel) const;
  // Mean focal length in pixels: converts angular thresholds to pixel ones and back.
  double MeanFocal() const;
  // Empty string if consistent; otherwise the problem (wrong parameter count, non-positive
  // focal or size, non-finite value, a distortion not invertible over the image: a grid of
  // pixels covering it, corners included, must all undistort, see UndistortPixel).
  std::string Validate() const;
};

// Distortion of normalised coordinates (u, v) -> (u + du, v + dv) for the model. `P` is the
// parameters' scalar: double for held intrinsics, the Jet T itself when they are unknowns
// (self-calibration, optim/intrinsics.h).
template <typename T, typename P>
void DistortNormalized(CameraModel model, const P* params, const T& u, const T& v, T* ud, T* vd);

// Pixel of a camera-frame point: the one projection used by every cost function.
template <typename T, typename P>
void ProjectToPixel(CameraModel model, const P* params, const T* x_cam, T* pixel);

// ---------------------------------------------------------------------------------------
template <typename T, typename P>
void DistortNormalized(CameraModel model, const P* p, const T& u, const T& v, T* ud, T* vd) {
  switch (model) {
    case CameraModel::kSimplePinhole:
    case CameraModel::kPinhole:
      *ud = u;
      *vd = v;
      return;
    case CameraModel::kSimpleRadial: {
      const T radial = T(p[3]) * (u * u + v * v);
      *ud = u + u * radial;
      *vd = v + v * radial;
      return;
    }
    case CameraModel::kRadial: {
      const T r2 = u * u + v * v;
      const T radial = T(p[3]) * r2 + T(p[4]) * r2 * r2;
      *ud = u + u * radial;
      *vd = v + v * radial;
      return;
    }
    case CameraModel::kOpenCV: {
      const T r2 = u * u + v * v;
      const T uv = u * v;
      const T radial = T(p[4]) * r2 + T(p[5]) * r2 * r2;
      *ud = u + u * radial + T(2.0) * T(p[6]) * uv + T(p[7]) * (r2 + T(2.0) * u * u);
      *vd = v + v * radial + T(2.0) * T(p[7]) * uv + T(p[6]) * (r2 + T(2.0) * v * v);
      return;
    }
  }
  *ud = u;  // not reached for valid models; keeps the outputs defined
  *vd = v;
}

template <typename T, typename P>
void ProjectToPixel(CameraModel model, const P* p, const T* x_cam, T* pixel) {
  const T u = x_cam[0] / x_cam[2];
  const T v = x_cam[1] / x_cam[2];
  T ud, vd;
  DistortNormalized(model, p, u, v, &ud, &vd);
  switch (model) {
    case CameraModel::kSimplePinhole:
    case CameraModel::kSimpleRadial:
    case CameraModel::kRadial:
      pixel[0] = T(p[0]) * ud + T(p[1]);
      pixel[1] = T(p[0]) * vd + T(p[2]);
      return;
    case CameraModel::kPinhole:
    case CameraModel::kOpenCV:
      pixel[0] = T(p[0]) * ud + T(p[2]);
      pixel[1] = T(p[1]) * vd + T(p[3]);
      return;
  }
  pixel[0] = ud;  // not reached for valid models; keeps the outputs defined
  pixel[1] = vd;
}

}  // namespace pgba
