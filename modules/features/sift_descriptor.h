// The SIFT descriptor (Lowe 2004): gradients of the keypoint's Gaussian layer in a window
// rotated to its orientation, accumulated with trilinear interpolation into 4x4 spatial
// cells x 8 orientation bins, Gaussian-weighted over the window, L2-normalised, clipped at
// 0.2 and normalised again (scaled to 512, as OpenCV's float output).
#pragma once

#include "features/sift_keypoints.h"

namespace pgba {

constexpr int kSiftCells = 4;         // spatial cells per side
constexpr int kSiftOrientations = 8;  // orientation bins per cell

// Descriptor of kp into out[0..127].
void ComputeSiftDescriptor(const SiftScaleSpace& ss, const SiftKeypoint& kp, float* out);

}  // namespace pgba
