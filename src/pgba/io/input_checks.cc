#include "pgba/io/input_checks.h"

#include <algorithm>
#include <cstdio>

#include "pgba/util/error.h"

namespace pgba {

std::string CheckCamera(const Camera& cam) {
  if (std::string problem = cam.Validate(); !problem.empty()) return problem;
  const double side = std::max(cam.width, cam.height);
  const bool separate = cam.model == CameraModel::kPinhole || cam.model == CameraModel::kOpenCV;
  const size_t principal = separate ? 2 : 1;
  for (size_t k = 0; k < principal; ++k) {
    const double f = cam.params[k];
    if (f < kMinFocalFraction * side || f > kMaxFocalFraction * side) {
      char buf[160];
      std::snprintf(buf, sizeof(buf), "focal length %.6g px is implausible for a %dx%d image (expected %.6g to %.6g px)",
                    f, cam.width, cam.height, kMinFocalFraction * side, kMaxFocalFraction * side);
      return buf;
    }
  }
  const double cx = cam.params[principal], cy = cam.params[principal + 1];
  if (!(cx >= 0 && cx <= cam.width && cy >= 0 && cy <= cam.height)) {
    char buf[160];
    std::snprintf(buf, sizeof(buf), "principal point (%.6g, %.6g) is outside the %dx%d image", cx, cy, cam.width,
                  cam.height);
    return buf;
  }
  return "";
}

std::string CheckImageName(const std::string& name) {
  if (name.empty()) return "empty image name";
  if (name.find_first_of(std::string("\n\r\0", 3)) != std::string::npos)
    return "image name " + QuotedName(name) + " holds a line break or NUL byte";
  const std::string space = " \t\v\f";
  if (space.find(name.front()) != std::string::npos || space.find(name.back()) != std::string::npos)
    return "image name " + QuotedName(name) + " begins or ends with whitespace, which a COLMAP text model cannot keep";
  return "";
}

std::string QuotedName(const std::string& name) {
  return "'" + OneLine(name.substr(0, 200)) + (name.size() > 200 ? "..." : "") + "'";
}

}  // namespace pgba
