#include "modules/synthetic/ground_footprint.h"

#include <algorithm>
#include <cmath>

namespace pgba::synthetic {
namespace {

double Cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

}  // namespace

GroundPolygon GroundFootprint(const Camera& camera, const Pose& pose, double ground_z) {
  const Eigen::Vector3d C = pose.C();
  const Eigen::Matrix3d Rt = pose.R().transpose();
  GroundPolygon poly;
  const double w = camera.width, h = camera.height;
  for (const Eigen::Vector2d& px :
       {Eigen::Vector2d(0, 0), Eigen::Vector2d(w, 0), Eigen::Vector2d(w, h), Eigen::Vector2d(0, h)}) {
    const Eigen::Vector3d ray = Rt * camera.PixelToBearing(px);
    const double t = (ground_z - C.z()) / ray.z();
    if (!(t > 0) || !std::isfinite(t)) return {};
    poly.push_back((C + t * ray).head<2>());
  }
  if (PolygonArea(poly) < 0) std::reverse(poly.begin(), poly.end());  // mirror-image orientation
  return poly;
}

double PolygonArea(const GroundPolygon& p) {
  double a = 0.0;
  for (size_t i = 0; i < p.size(); ++i) a += Cross(p[i], p[(i + 1) % p.size()]);
  return 0.5 * a;
}

GroundPolygon IntersectConvex(const GroundPolygon& a, const GroundPolygon& b) {
  GroundPolygon out = a;
  for (size_t e = 0; e < b.size() && !out.empty(); ++e) {
    const Eigen::Vector2d p = b[e], d = b[(e + 1) % b.size()] - p;
    // Inside = left of the counter-clockwise edge.
    const auto side = [&](const Eigen::Vector2d& x) { return Cross(d, x - p); };
    GroundPolygon in = std::move(out);
    out.clear();
    for (size_t i = 0; i < in.size(); ++i) {
      const Eigen::Vector2d& u = in[i];
      const Eigen::Vector2d& v = in[(i + 1) % in.size()];
      const double su = side(u), sv = side(v);
      if (su >= 0) out.push_back(u);
      if ((su >= 0) != (sv >= 0)) out.push_back(u + (v - u) * (su / (su - sv)));
    }
  }
  return out;
}

double FootprintOverlap(const GroundPolygon& a, const GroundPolygon& b) {
  if (a.size() < 3 || b.size() < 3) return 0.0;
  const double smaller = std::min(PolygonArea(a), PolygonArea(b));
  if (!(smaller > 0)) return 0.0;
  const GroundPolygon both = IntersectConvex(a, b);
  return both.size() < 3 ? 0.0 : std::clamp(PolygonArea(both) / smaller, 0.0, 1.0);
}

}  // namespace pgba::synthetic
