#include "pgba/scene/triangulate_model.h"

#include <tbb/parallel_for.h>

#include <vector>

namespace pgba {

Reconstruction TriangulateModel(const Reconstruction& tracks, const std::map<uint32_t, Pose>& poses,
                                const TriangulationOptions& options) {
  Reconstruction out = tracks;
  std::vector<uint32_t> keep;
  for (const auto& [id, pose] : poses)
    if (out.images.count(id)) {
      out.images[id].pose = pose;
      keep.push_back(id);
    }
  out.KeepImages(keep);

  std::vector<Point3D*> points;
  points.reserve(out.points3D.size());
  for (auto& [id, p] : out.points3D) points.push_back(&p);
  std::vector<char> ok(points.size(), 0);
  // Each task writes only its own point and slot: the result is independent of scheduling.
  tbb::parallel_for(size_t(0), points.size(), [&](size_t i) {
    Point3D& p = *points[i];
    std::vector<TrackView> views;
    views.reserve(p.track.size());
    for (const auto& e : p.track) {
      const Image& im = out.images.at(e.image_id);
      views.push_back({im.pose, &out.cameras.at(im.camera_id), im.points2D[e.point2D_idx].xy});
    }
    const TriangulatedPoint t = TriangulateTrack(views, options);
    if (!t.ok) return;
    double sum = 0;
    int n = 0;
    for (double r : t.residuals_px)
      if (r < options.outlier_px) sum += r, ++n;
    if (n < 2) return;
    p.xyz = t.X;
    p.error = sum / n;
    ok[i] = 1;
  });
  std::vector<uint64_t> failed;
  for (size_t i = 0; i < points.size(); ++i)
    if (!ok[i]) failed.push_back(points[i]->point3D_id);
  for (uint64_t id : failed) out.DeletePoint3D(id);
  return out;
}

}  // namespace pgba
