#include "evaluation/sigma.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "pgba/io/option_ranges.h"
#include "evaluation/statistics.h"
#include "pgba/geometry/triangulation.h"

namespace pgba {

RegisteredViews MatchImagesByName(const Reconstruction& model, const Reconstruction& obs) {
  std::map<std::string, const Image*> by_name;
  for (const auto& [id, im] : model.images) by_name.emplace(im.name, &im);
  RegisteredViews views;
  for (const auto& [id, im] : obs.images) {
    auto it = by_name.find(im.name);
    if (it == by_name.end()) continue;
    views.poses.emplace(id, it->second->pose);
    views.cameras.emplace(id, &model.CameraOf(*it->second));
  }
  return views;
}

namespace {

// Outcome of one track, written into its own slot by the parallel loop.
struct TrackSlot {
  size_t num_views = 0;        // registered views (0 when the track is not evaluated)
  bool triangulated = false;
  std::vector<double> residuals_px;
};

TrackSlot EvaluateTrack(const Reconstruction& obs, const Point3D& point, const PoseMap& poses,
                        const CameraRefMap* cameras, const TriangulationOptions& tri) {
  std::vector<TrackView> views;
  views.reserve(point.track.size());
  for (const TrackElement& el : point.track) {
    auto pose = poses.find(el.image_id);
    if (pose == poses.end()) continue;  // unregistered image: its observation is skipped
    const Image& image = obs.images.at(el.image_id);
    TrackView v;
    v.pose = pose->second;
    v.camera = &obs.CameraOf(image);
    if (cameras) {
      auto cam = cameras->find(el.image_id);
      if (cam != cameras->end()) v.camera = cam->second;
    }
    v.pixel = image.points2D.at(el.point2D_idx).xy;
    views.push_back(v);
  }
  TrackSlot slot;
  if (views.size() < 2) return slot;
  slot.num_views = views.size();
  TriangulatedPoint p = TriangulateTrack(views, tri);
  slot.triangulated = p.ok;
  if (p.ok) slot.residuals_px = std::move(p.residuals_px);
  return slot;
}

}  // namespace

SigmaResult EvaluateSigma(const Reconstruction& obs, const PoseMap& poses, const SigmaOptions& options,
                          const CameraRefMap* cameras) {
  std::vector<const Point3D*> points;
  points.reserve(obs.points3D.size());
  for (const auto& [id, p] : obs.points3D) points.push_back(&p);

  TriangulationOptions tri;
  tri.huber_px = options.huber_px;
  tri.outlier_px = options.inlier_px;
  tri.max_iterations = options.max_iterations;

  std::vector<TrackSlot> slots(points.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, points.size()), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) slots[i] = EvaluateTrack(obs, *points[i], poses, cameras, tri);
  });

  // Reduce in track order so that the result does not depend on the TBB schedule.
  SigmaResult out;
  std::vector<double> all, inliers;
  const auto huber = [&](double e) {
    return e <= options.huber_px ? e * e : 2.0 * options.huber_px * e - options.huber_px * options.huber_px;
  };
  const double cap = huber(options.inlier_px);
  for (const TrackSlot& s : slots) {
    if (s.num_views == 0) continue;
    ++out.num_tracks;
    out.num_observations += s.num_views;
    if (!s.triangulated) {
      out.robust_cost += cap * static_cast<double>(s.num_views);
      continue;
    }
    // One view under inlier_px is no reprojection error: a point constrained by one ray lies
    // anywhere on it (at ~1e15 for an outlier track whose Huber estimate runs to infinity, where
    // the residual in that view is chaotic in the poses). Such observations count as outliers,
    // and such a track is no point (TriangulateModel keeps none either).
    const size_t agreeing = static_cast<size_t>(std::count_if(
        s.residuals_px.begin(), s.residuals_px.end(), [&](double e) { return e < options.inlier_px; }));
    out.num_triangulated += agreeing >= 2;
    for (double e : s.residuals_px) {
      all.push_back(e);
      out.robust_cost += std::min(huber(e), cap);
      if (agreeing >= 2 && e < options.inlier_px) inliers.push_back(e);
    }
  }
  out.num_inliers = inliers.size();
  if (!inliers.empty()) out.rms = Rms(inliers);
  if (!all.empty()) out.median = Median(all);
  if (out.num_observations > 0)
    out.inlier_fraction = static_cast<double>(out.num_inliers) / static_cast<double>(out.num_observations);
  return out;
}

std::string SigmaOptions::Check() const {
  return CheckRanges(*this, "SigmaOptions");
}

}  // namespace pgba
