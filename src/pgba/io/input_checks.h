// The checks every reader of a camera or an image name applies, and every converter applies
// to what it writes, so that a file pgba writes is one pgba reads back the same.
#pragma once

#include <string>

#include "pgba/scene/camera.h"

namespace pgba {

// Empty when `cam` is usable as a calibration, else the problem: Camera::Validate() (parameter
// count, finite values, positive focal and size, invertible distortion), a focal outside
// [kMinFocalFraction, kMaxFocalFraction] x the larger image side (1e-9 or 1e300 px is a unit
// or typing error, not a lens), or a principal point outside the image.
constexpr double kMinFocalFraction = 0.01;
constexpr double kMaxFocalFraction = 1000.0;
std::string CheckCamera(const Camera& cam);

// Empty when `name` survives a COLMAP images.txt line unchanged (the NAME field is the rest
// of the line, trailing whitespace dropped), else the problem: empty, a line break or NUL
// byte, or whitespace at either end.
std::string CheckImageName(const std::string& name);

// `name` made safe for a one-line message (control bytes escaped, quoted).
std::string QuotedName(const std::string& name);

}  // namespace pgba
