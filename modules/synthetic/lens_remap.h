// Rendering through a distorting lens: the quads are rendered into a pinhole "canvas" that
// covers every ray of the distorted image, and each output pixel samples the canvas where
// its own ray lands (undistort pixel -> ray -> canvas pixel; cv::remap, bilinear), on the
// supersampled grid before the box filter. So an image point drawn at pixel p is the scene
// point whose ray Camera::PixelToNormalized(p) gives: exactly what Camera::Project inverts.
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <vector>

#include "modules/synthetic/quad_renderer.h"

namespace pgba::synthetic {

class LensRenderer {
 public:
  // `camera`: any model whose distortion is invertible over the image (Camera::Validate;
  // asserted). `supersampling` >= 1 as in RenderQuads.
  LensRenderer(const Camera& camera, int supersampling);

  // As RenderQuads, through the lens; for a pinhole camera exactly RenderQuads.
  cv::Mat Render(const std::vector<TexturedQuad>& quads, const Pose& pose) const;

  // The pinhole canvas (already at the supersampled resolution) and where output pixel
  // `pixel` (continuous, COLMAP convention, of the camera's image) samples it.
  const Camera& canvas() const { return canvas_; }
  Eigen::Vector2d CanvasPixelOf(const Eigen::Vector2d& pixel) const;

 private:
  Camera camera_;
  Camera canvas_;
  int supersampling_ = 1;
  bool pinhole_ = true;
  cv::Mat map_x_, map_y_;  // CV_32F, supersampled output grid -> canvas (OpenCV indices)
};

}  // namespace pgba::synthetic
