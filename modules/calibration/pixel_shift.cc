#include "modules/calibration/pixel_shift.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace pgba {

double MaxPixelShift(const Camera& from, const Camera& to, int n) {
  if (n < 2) throw std::invalid_argument("MaxPixelShift: grid needs n >= 2");
  if (from.width != to.width || from.height != to.height)
    throw std::invalid_argument("MaxPixelShift: cameras of different image sizes");
  constexpr double kInf = std::numeric_limits<double>::infinity();
  double worst = 0.0;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const Eigen::Vector2d p((from.width - 1) * double(i) / (n - 1), (from.height - 1) * double(j) / (n - 1));
      Eigen::Vector2d normalized;
      if (!from.UndistortPixel(p, &normalized)) return kInf;
      const Eigen::Vector3d ray(normalized.x(), normalized.y(), 1.0);
      const Eigen::Vector2d q = to.Project(ray);
      if (!q.allFinite()) return kInf;
      worst = std::max(worst, (q - p).norm());
    }
  }
  return worst;
}

double MaxPixelShift(const std::map<uint32_t, Camera>& from, const std::map<uint32_t, Camera>& to) {
  double worst = 0.0;
  for (const auto& [id, camera] : from) {
    const auto it = to.find(id);
    if (it != to.end()) worst = std::max(worst, MaxPixelShift(camera, it->second));
  }
  return worst;
}

}  // namespace pgba
