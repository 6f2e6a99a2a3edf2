// Shared by the synthetic scene tests: generation shorthand and independent checks against
// the ground truth (reprojection, view-graph connectivity).
#pragma once

#include <functional>
#include <map>
#include <set>

#include "modules/synthetic/synthetic_scene.h"

namespace pgba::test {

constexpr double kRadToDeg = 180.0 / M_PI;

inline double ReprojectionError(const Reconstruction& rec, const Image& im, const Point2D& obs) {
  const Point3D& p = rec.points3D.at(static_cast<uint64_t>(obs.point3D_id));
  return (rec.CameraOf(im).Project(im.pose.ToCamera(p.xyz)) - obs.xy).norm();
}

// Union-find over images linked by a common track.
inline bool ViewGraphConnected(const Reconstruction& rec) {
  std::map<uint32_t, uint32_t> parent;
  for (const auto& [id, im] : rec.images) parent[id] = id;
  std::function<uint32_t(uint32_t)> find = [&](uint32_t x) { return parent[x] == x ? x : parent[x] = find(parent[x]); };
  for (const auto& [pid, p] : rec.points3D)
    for (const auto& e : p.track) parent[find(e.image_id)] = find(p.track.front().image_id);
  std::set<uint32_t> roots;
  for (const auto& [id, im] : rec.images) roots.insert(find(id));
  return roots.size() == 1;
}

inline SyntheticScene Generate(SyntheticScenario scenario, double noise, double outliers, uint64_t seed = 1,
                               int images = 0) {
  SyntheticOptions o;
  o.scenario = scenario;
  o.noise_px = noise;
  o.outlier_fraction = outliers;
  o.seed = seed;
  o.num_images = images;
  return GenerateSyntheticScene(o);
}

}  // namespace pgba::test
