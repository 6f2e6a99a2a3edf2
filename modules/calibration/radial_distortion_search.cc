#include "modules/calibration/radial_distortion_search.h"

#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "modules/calibration/grid_search.h"

namespace pgba {
namespace {

bool HasTwoFocals(CameraModel m) { return m == CameraModel::kPinhole || m == CameraModel::kOpenCV; }

// Sum of the truncated squared Sampson distances of the pair after refinement under `camera`.
double PairCost(const Camera& camera, const PairPixels& pair, const FundamentalMatrixOptions& options) {
  const std::vector<Eigen::Vector2d> x1 = PinholePixels(camera, pair.x1), x2 = PinholePixels(camera, pair.x2);
  const FundamentalMatrixResult r = RefineFundamentalMatrix(x1, x2, pair.F, options);
  const double cap = options.threshold_px * options.threshold_px;
  double sum = 0.0;
  for (size_t i = 0; i < x1.size(); ++i) {
    const double d = r.success ? SampsonDistance(r.F, x1[i], x2[i]) : INFINITY;
    sum += std::min(d * d, cap);
  }
  return sum;
}

}  // namespace

Eigen::Matrix3d PinholeMatrix(const Camera& c) {
  const std::vector<double>& p = c.params;
  const bool two = HasTwoFocals(c.model);
  const double fx = p[0], fy = two ? p[1] : p[0], cx = two ? p[2] : p[1], cy = two ? p[3] : p[2];
  Eigen::Matrix3d K;
  K << fx, 0, cx, 0, fy, cy, 0, 0, 1;
  return K;
}

std::vector<Eigen::Vector2d> PinholePixels(const Camera& camera, const std::vector<Eigen::Vector2d>& pixels) {
  const Eigen::Matrix3d K = PinholeMatrix(camera);
  std::vector<Eigen::Vector2d> out;
  out.reserve(pixels.size());
  for (const Eigen::Vector2d& p : pixels) out.push_back((K * camera.PixelToNormalized(p).homogeneous()).hnormalized());
  return out;
}

int RadialCoefficientIndex(CameraModel model) {
  switch (model) {
    case CameraModel::kSimpleRadial:
    case CameraModel::kRadial:
      return 3;
    case CameraModel::kOpenCV:
      return 4;
    default:
      return -1;
  }
}

RadialSearchResult SearchRadialDistortion(const Camera& camera, const std::vector<const PairPixels*>& pairs,
                                          const FundamentalMatrixOptions& options, double max_abs_k1) {
  RadialSearchResult result;
  const int index = RadialCoefficientIndex(camera.model);
  if (index < 0 || pairs.empty()) return result;
  std::vector<double> slot(pairs.size());
  const auto cost = [&](double k1) {
    Camera c = camera;
    c.params[index] = k1;
    if (!c.Validate().empty()) return double(INFINITY);
    tbb::parallel_for(size_t(0), pairs.size(), [&](size_t i) { slot[i] = PairCost(c, *pairs[i], options); });
    double sum = 0.0;
    for (double v : slot) sum += v;  // in pair order: the same sum whatever the scheduling
    return sum;
  };
  const GridMinimum m = MinimiseByGridAndGoldenSection(cost, -max_abs_k1, max_abs_k1, 21, 1e-4 * max_abs_k1);
  result.searched = true;
  result.k1 = m.x;
  result.cost = m.cost;
  result.cost_at_zero = cost(0.0);
  return result;
}

}  // namespace pgba
