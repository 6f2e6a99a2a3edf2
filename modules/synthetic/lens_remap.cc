#include "modules/synthetic/lens_remap.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

namespace pgba::synthetic {

LensRenderer::LensRenderer(const Camera& camera, int supersampling)
    : camera_(camera), supersampling_(supersampling) {
  CV_Assert(supersampling >= 1 && camera.Validate().empty());
  pinhole_ = camera.model == CameraModel::kPinhole || camera.model == CameraModel::kSimplePinhole;
  if (pinhole_) return;
  const int s = supersampling;
  // The rays of the image border bound the canvas (the undistorted radius grows
  // monotonically with the distorted one over an invertible image, so the border's rays
  // enclose every ray of the interior).
  Eigen::Vector2d lo(INFINITY, INFINITY), hi(-INFINITY, -INFINITY);
  const int n = 64;
  for (int i = 0; i <= n; ++i) {
    const double a = double(i) / n;
    for (const Eigen::Vector2d& p :
         {Eigen::Vector2d(a * camera.width, 0), Eigen::Vector2d(a * camera.width, camera.height),
          Eigen::Vector2d(0, a * camera.height), Eigen::Vector2d(camera.width, a * camera.height)}) {
      const Eigen::Vector2d u = camera.PixelToNormalized(p);
      lo = lo.cwiseMin(u);
      hi = hi.cwiseMax(u);
    }
  }
  // Canvas: square pixels of the camera's mean focal times s, two pixels of margin for the
  // bilinear interpolation.
  const double f = s * camera.MeanFocal();
  const double margin = 2.0;
  canvas_.model = CameraModel::kPinhole;
  canvas_.width = static_cast<int>(std::ceil((hi.x() - lo.x()) * f + 2 * margin));
  canvas_.height = static_cast<int>(std::ceil((hi.y() - lo.y()) * f + 2 * margin));
  canvas_.params = {f, f, margin - lo.x() * f, margin - lo.y() * f};
  map_x_.create(camera.height * s, camera.width * s, CV_32F);
  map_y_.create(camera.height * s, camera.width * s, CV_32F);
  for (int j = 0; j < map_x_.rows; ++j)
    for (int i = 0; i < map_x_.cols; ++i) {
      // Output sample (i, j) covers the continuous pixel ((i + 0.5) / s, (j + 0.5) / s);
      // a canvas position x (continuous) is OpenCV index x - 0.5.
      const Eigen::Vector2d c = CanvasPixelOf(Eigen::Vector2d((i + 0.5) / s, (j + 0.5) / s));
      map_x_.at<float>(j, i) = static_cast<float>(c.x() - 0.5);
      map_y_.at<float>(j, i) = static_cast<float>(c.y() - 0.5);
    }
}

Eigen::Vector2d LensRenderer::CanvasPixelOf(const Eigen::Vector2d& pixel) const {
  if (pinhole_) return pixel * supersampling_;
  return canvas_.Project(camera_.PixelToNormalized(pixel).homogeneous());
}

cv::Mat LensRenderer::Render(const std::vector<TexturedQuad>& quads, const Pose& pose) const {
  if (pinhole_) return RenderQuads(quads, camera_, pose, supersampling_);
  const cv::Mat canvas = RenderQuads(quads, canvas_, pose, 1);
  cv::Mat sampled;
  cv::remap(canvas, sampled, map_x_, map_y_, cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar::all(0));
  if (supersampling_ == 1) return sampled;
  cv::Mat out;
  cv::resize(sampled, out, cv::Size(camera_.width, camera_.height), 0, 0, cv::INTER_AREA);
  return out;
}

}  // namespace pgba::synthetic
