// Rendering of textured planar rectangles into a pinhole camera: each rectangle's texture
// is mapped by its plane-induced homography (cv::warpPerspective) and composited with a
// per-pixel z-buffer, on a supersampled grid that is then box-filtered down (cv::resize
// INTER_AREA), which anti-aliases edges and minified textures.
//
// Pixel conventions are COLMAP's: the centre of the upper-left pixel is (0.5, 0.5), so a
// point projected by Camera::Project lands on the pixel the renderer drew it in. The inverse
// depth of a plane is affine in the pixel coordinates; its sign tells whether the ray meets
// the plane in front of the camera, which handles rectangles that pass behind the camera
// (walls of a room around it) without clipping polygons.
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <vector>

#include "pgba/geometry/pose.h"
#include "pgba/scene/camera.h"

namespace pgba::synthetic {

// Texel (a, b) of `texture` (OpenCV indices; its centre is at (a + 0.5, b + 0.5) in
// continuous texture coordinates) shows the world point
//   origin + (a + 0.5) / W * u_axis + (b + 0.5) / H * v_axis,   W x H = texture size,
// so the rectangle spans origin + [0, 1] u_axis + [0, 1] v_axis.
struct TexturedQuad {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  Eigen::Vector3d u_axis = Eigen::Vector3d::UnitX();
  Eigen::Vector3d v_axis = Eigen::Vector3d::UnitY();
  cv::Mat texture;  // CV_8UC3
};

// The image (CV_8UC3, camera.width x camera.height) of `quads` seen from `pose`; pixels no
// quad covers are black. Camera: PINHOLE or SIMPLE_PINHOLE (asserted: distortion would
// need a remap). `supersampling` >= 1 rendered samples per pixel and axis.
cv::Mat RenderQuads(const std::vector<TexturedQuad>& quads, const Camera& camera, const Pose& pose,
                    int supersampling);

}  // namespace pgba::synthetic
