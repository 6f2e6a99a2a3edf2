// Helpers of the tests of models on a synthetic orbit: the true two-view geometry of its image
// pairs, a model of some of its images in another frame, and its tracks cut between two arcs.
#pragma once

#include <algorithm>
#include <map>
#include <utility>
#include <vector>

#include "averaging/global_init.h"
#include "pgba/geometry/rotation.h"
#include "pgba/geometry/sim3.h"
#include "pgba/scene/reconstruction.h"
#include "pgba/scene/view_graph.h"
#include "synthetic/synthetic_scene.h"

namespace pgba::test {

inline SyntheticScene Orbit(uint64_t seed = 5, int num_images = 40) {
  SyntheticOptions so;
  so.scenario = SyntheticScenario::kOrbit;
  so.seed = seed;
  so.num_images = num_images;
  so.noise_px = 0.5;
  return GenerateSyntheticScene(so);
}

// The true two-view rotation and translation direction of every pair of images sharing at
// least 30 tracks.
inline std::vector<TwoViewGeometry> TruePairs(const Reconstruction& gt) {
  std::map<std::pair<uint32_t, uint32_t>, int> shared;
  for (const auto& [id, point] : gt.points3D)
    for (size_t a = 0; a < point.track.size(); ++a)
      for (size_t b = a + 1; b < point.track.size(); ++b)
        ++shared[std::minmax(point.track[a].image_id, point.track[b].image_id)];
  std::vector<TwoViewGeometry> pairs;
  for (const auto& [ids, n] : shared) {
    if (n < 30) continue;
    TwoViewGeometry p;
    p.image_id1 = ids.first;
    p.image_id2 = ids.second;
    const Pose& p1 = gt.images.at(ids.first).pose;
    const Pose& p2 = gt.images.at(ids.second).pose;
    p.R_21 = p2.R() * p1.R().transpose();
    p.t_21 = (p2.t() - p.R_21 * p1.t()).normalized();
    p.num_tracks = n;
    pairs.push_back(p);
  }
  return pairs;
}

inline Sim3 SomeSimilarity() {
  Sim3 s;
  s.s = 2.5;
  s.R = ExpSO3(Eigen::Vector3d(0.3, -0.2, 0.5));
  s.t = Eigen::Vector3d(4.0, -1.0, 2.0);
  return s;
}

// The true poses of `ids` moved by `frame`, as a model.
inline GlobalInitResult ModelOf(const Reconstruction& gt, const std::vector<uint32_t>& ids, const Sim3& frame) {
  GlobalInitResult m;
  m.success = true;
  for (uint32_t id : ids) m.poses[id] = frame.Apply(gt.images.at(id).pose);
  return m;
}

// The tracks cut where they cross between the images below `split` and the rest: each
// track's part on either side becomes a track of its own (parts of one view dropped).
inline Reconstruction CutTracks(const Reconstruction& tracks, uint32_t split) {
  Reconstruction cut = tracks;
  for (auto& [id, image] : cut.images)
    for (Point2D& p : image.points2D) p.point3D_id = kNoPoint3D;
  cut.points3D.clear();
  for (const auto& [id, point] : tracks.points3D) {
    std::vector<TrackElement> low, high;
    for (const TrackElement& e : point.track) (e.image_id < split ? low : high).push_back(e);
    for (const std::vector<TrackElement>* part : {&low, &high})
      if (part->size() >= 2) cut.AddPoint3D(point.xyz, *part);
  }
  return cut;
}

}  // namespace pgba::test
