// Lens options of the synthetic scenes (tracks and rendered), so that self-calibration has an
// exact truth: the true camera gets a radial distortion k1, and the calibration handed to the
// pipeline is a wrong focal prior without distortion (what a user without a lab calibration
// has: a focal guess, no distortion model).
#pragma once

#include <string>

#include "pgba/scene/camera.h"
#include "pgba/util/error.h"

namespace pgba::synthetic {

// `pinhole` (PINHOLE or SIMPLE_PINHOLE) with the one-coefficient radial distortion
// u_d = u (1 + k1 |u|^2) of normalised coordinates u. k1 = 0 returns `pinhole` unchanged;
// otherwise SIMPLE_RADIAL (f, cx, cy, k1) when fx == fy, else OPENCV (fx, fy, cx, cy, k1,
// 0, 0, 0), the same distortion with two focals. InputError naming `option` when k1 is not
// finite or the distortion is not invertible over the image (Camera::Validate).
Camera WithRadialDistortion(const Camera& pinhole, double k1, const std::string& option);

// The calibration a user would hand in: every focal of `truth` times (1 + relative_error),
// the same principal point, every distortion coefficient 0 (same model as the truth).
Camera FocalPrior(const Camera& truth, double relative_error);

// Range checks of the two options, InputError naming the option: |k1| <= 1 (the
// invertibility over the image is checked by WithRadialDistortion) and the relative focal
// error in [-0.5, 1].
void ValidateLensOptions(double k1, const std::string& k1_option, double focal_prior_error,
                         const std::string& error_option);

// The message of the InputError `validate(options)` throws, empty if none: the Check() of the
// synthetic scenes' options, whose validators name the CLI flags.
template <typename Options>
std::string ValidationMessage(void (*validate)(const Options&), const Options& options) {
  try {
    validate(options);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace pgba::synthetic
