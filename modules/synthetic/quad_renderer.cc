#include "modules/synthetic/quad_renderer.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <opencv2/core/eigen.hpp>
#include <opencv2/imgproc.hpp>

namespace pgba::synthetic {
namespace {

// Intrinsics of the supersampled image: continuous coordinates scale about the image corner.
Eigen::Matrix3d SupersampledK(const Camera& camera, int s) {
  CV_Assert(camera.model == CameraModel::kPinhole || camera.model == CameraModel::kSimplePinhole);
  const std::vector<double>& p = camera.params;
  const bool simple = camera.model == CameraModel::kSimplePinhole;
  const double fx = p[0], fy = simple ? p[0] : p[1], cx = simple ? p[1] : p[2], cy = simple ? p[2] : p[3];
  Eigen::Matrix3d K;
  K << s * fx, 0, s * cx, 0, s * fy, s * cy, 0, 0, 1;
  return K;
}

Eigen::Matrix3d Translation(double dx, double dy) {
  Eigen::Matrix3d T = Eigen::Matrix3d::Identity();
  T(0, 2) = dx;
  T(1, 2) = dy;
  return T;
}

// Supersampled pixel rectangle the quad can cover: the bounding box of its projected
// corners when all four are in front of the camera, else the whole image (a rectangle
// crossing the camera plane projects to an unbounded region). Empty if all are behind.
cv::Rect CoverRect(const TexturedQuad& q, const Eigen::Matrix3d& K, const Eigen::Matrix3d& R,
                   const Eigen::Vector3d& C, cv::Size size) {
  const cv::Rect full(0, 0, size.width, size.height);
  double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
  int behind = 0;
  for (const Eigen::Vector3d& X : {q.origin, Eigen::Vector3d(q.origin + q.u_axis), Eigen::Vector3d(q.origin + q.v_axis),
                                   Eigen::Vector3d(q.origin + q.u_axis + q.v_axis)}) {
    const Eigen::Vector3d x = K * (R * (X - C));
    if (x.z() <= 1e-9) {
      ++behind;
      continue;
    }
    x0 = std::min(x0, x.x() / x.z());
    x1 = std::max(x1, x.x() / x.z());
    y0 = std::min(y0, x.y() / x.z());
    y1 = std::max(y1, x.y() / x.z());
  }
  if (behind == 4) return {};
  if (behind > 0) return full;
  const auto clampi = [](double v, int hi) { return static_cast<int>(std::clamp(v, 0.0, static_cast<double>(hi))); };
  const int ix0 = clampi(std::floor(x0) - 1, size.width), iy0 = clampi(std::floor(y0) - 1, size.height);
  const int ix1 = clampi(std::ceil(x1) + 1, size.width), iy1 = clampi(std::ceil(y1) + 1, size.height);
  return cv::Rect(ix0, iy0, ix1 - ix0, iy1 - iy0) & full;
}

}  // namespace

cv::Mat RenderQuads(const std::vector<TexturedQuad>& quads, const Camera& camera, const Pose& pose,
                    int supersampling) {
  CV_Assert(supersampling >= 1 && camera.width > 0 && camera.height > 0);
  const int s = supersampling;
  const cv::Size size(camera.width * s, camera.height * s);
  const Eigen::Matrix3d K = SupersampledK(camera, s);
  const Eigen::Matrix3d Kinv = K.inverse();
  const Eigen::Matrix3d R = pose.R();
  const Eigen::Vector3d C = pose.C();

  cv::Mat colour(size, CV_8UC3, cv::Scalar::all(0));
  // Inverse depth of the nearest surface drawn so far; 0 = nothing yet (infinitely far).
  cv::Mat inv_depth(size, CV_32F, cv::Scalar(0));
  for (const TexturedQuad& q : quads) {
    CV_Assert(q.texture.type() == CV_8UC3 && !q.texture.empty());
    const Eigen::Vector3d n = q.u_axis.cross(q.v_axis);
    const double dist = n.dot(q.origin - C);  // signed distance to the plane times |n|
    if (std::abs(dist) < 1e-9 * n.norm()) continue;  // plane through the centre: seen edge-on
    const cv::Rect roi = CoverRect(q, K, R, C, size);
    if (roi.empty()) continue;

    // Texture index -> supersampled pixel index of the ROI (both OpenCV, centres at integers).
    const double tw = q.texture.cols, th = q.texture.rows;
    Eigen::Matrix3d A;
    A.col(0) = R * q.u_axis / tw;
    A.col(1) = R * q.v_axis / th;
    A.col(2) = R * (q.origin - C);
    const Eigen::Matrix3d H = Translation(-0.5 - roi.x, -0.5 - roi.y) * K * A * Translation(0.5, 0.5);
    const Eigen::Matrix3d Hinv = H.inverse();
    cv::Mat Hcv;
    cv::eigen2cv(H, Hcv);
    cv::Mat warped;
    // Replicated border: pixels on the rectangle's edge blend with its own edge texels, not
    // with black; coverage is decided exactly below.
    cv::warpPerspective(q.texture, warped, Hcv, roi.size(), cv::INTER_LINEAR, cv::BORDER_REPLICATE);

    // Inverse depth along the ray of continuous pixel x: (R n) . (Kinv x) / dist.
    const Eigen::Vector3d g = (Kinv.transpose() * (R * n)) / dist;
    for (int j = 0; j < roi.height; ++j) {
      const double y = roi.y + j + 0.5;
      float* zrow = inv_depth.ptr<float>(roi.y + j) + roi.x;
      cv::Vec3b* crow = colour.ptr<cv::Vec3b>(roi.y + j) + roi.x;
      const cv::Vec3b* wrow = warped.ptr<cv::Vec3b>(j);
      for (int i = 0; i < roi.width; ++i) {
        const double x = roi.x + i + 0.5;
        const double iz = g.x() * x + g.y() * y + g.z();
        if (!(iz > zrow[i])) continue;  // behind the camera (iz <= 0) or hidden
        const Eigen::Vector3d t = Hinv * Eigen::Vector3d(i, j, 1.0);
        const double a = t.x() / t.z() + 0.5, b = t.y() / t.z() + 0.5;  // continuous texture coords
        if (a < 0 || a > tw || b < 0 || b > th) continue;
        zrow[i] = static_cast<float>(iz);
        crow[i] = wrow[i];
      }
    }
  }
  if (s == 1) return colour;
  cv::Mat out;
  cv::resize(colour, out, cv::Size(camera.width, camera.height), 0, 0, cv::INTER_AREA);
  return out;
}

}  // namespace pgba::synthetic
