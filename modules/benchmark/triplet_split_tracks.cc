#include "benchmark/triplet_split_tracks.h"

#include <algorithm>

namespace pgba {

Reconstruction SplitTracksByMotions(const Reconstruction& tracks, const std::vector<LocalMotion>& motions) {
  Reconstruction split = tracks;
  split.points3D.clear();
  for (auto& [id, image] : split.images)
    for (Point2D& p : image.points2D) p.point3D_id = kNoPoint3D;
  std::vector<TrackElement> elements;
  for (const LocalMotion& t : motions) {
    for (const auto& [point_id, point] : tracks.points3D) {
      elements.clear();
      for (const TrackElement& e : point.track) {
        if (std::find(t.image_ids.begin(), t.image_ids.end(), e.image_id) == t.image_ids.end()) continue;
        Image& image = split.images.at(e.image_id);
        Point2D copy;
        copy.xy = tracks.images.at(e.image_id).points2D.at(e.point2D_idx).xy;
        image.points2D.push_back(copy);
        elements.push_back({e.image_id, static_cast<uint32_t>(image.points2D.size() - 1)});
      }
      if (elements.size() >= 2) {
        split.AddPoint3D(point.xyz, elements);
      } else {
        for (const TrackElement& e : elements) split.images.at(e.image_id).points2D.pop_back();
      }
    }
  }
  return split;
}

}  // namespace pgba
