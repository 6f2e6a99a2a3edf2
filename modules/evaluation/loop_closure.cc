#include "evaluation/loop_closure.h"

#include <map>
#include <string>

#include "evaluation/statistics.h"
#include "pgba/geometry/triangulation.h"

namespace pgba {

LoopClosureResult EvaluateLoopClosure(const Reconstruction& model, const std::vector<LoopCorrespondence>& loops) {
  std::map<std::string, const Image*> by_name;
  for (const auto& [id, im] : model.images) by_name.emplace(im.name, &im);
  auto view_of = [&](const std::string& name, const Eigen::Vector2d& xy, TrackView* v) {
    auto it = by_name.find(name);
    if (it == by_name.end()) return false;
    v->pose = it->second->pose;
    v->camera = &model.CameraOf(*it->second);
    v->pixel = xy;
    return true;
  };

  LoopClosureResult out;
  out.num_correspondences = loops.size();
  std::vector<double> residuals;
  // Two-view triangulations are cheap: a serial loop keeps the order (and the result) fixed.
  for (const LoopCorrespondence& c : loops) {
    std::vector<TrackView> views(2);
    if (!view_of(c.name_i, c.xy_i, &views[0]) || !view_of(c.name_j, c.xy_j, &views[1])) {
      ++out.num_unregistered;
      continue;
    }
    const TriangulatedPoint p = TriangulateTrack(views);
    if (!p.ok) {
      ++out.num_failed;
      continue;
    }
    ++out.num_evaluated;
    residuals.insert(residuals.end(), p.residuals_px.begin(), p.residuals_px.end());
  }
  if (out.num_evaluated > 0) {
    out.rms = Rms(residuals);
    out.median = Median(residuals);
  }
  return out;
}

}  // namespace pgba
