// How far a change of calibration moves the image: the pixel that camera `to` gives a ray
// seen by camera `from` at pixel p, against p, as the largest distance over a grid of the image
// (corners included, where distortion and focal changes show most). Used by `pgba run` to tell
// whether the matches verified with the prior cameras still hold for the refined ones
// (ViewGraphCalibrationOptions::rematch_shift_px).
#pragma once

#include <cstdint>
#include <map>

#include "pgba/scene/camera.h"

namespace pgba {

// Largest |to(from^-1(p)) - p| in pixels over a (n x n) grid of `from`'s image (n >= 2); the
// two cameras must have the same size. Infinity when a pixel has no ray in `from` or projects
// behind `to`.
double MaxPixelShift(const Camera& from, const Camera& to, int n = 9);

// The largest MaxPixelShift over the cameras present in both maps (0 if none).
double MaxPixelShift(const std::map<uint32_t, Camera>& from, const std::map<uint32_t, Camera>& to);

}  // namespace pgba
