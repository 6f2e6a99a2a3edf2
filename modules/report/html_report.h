// report.html of `pgba run`: the page a user opens first. Self-contained (inline SVG, CSS and
// scripts, no external resource: it works offline and from a copied folder): summary table,
// ground-truth errors when known, a 3D view of the cameras and points (report/model_view_3d.h),
// per-stage timings, the pointless BA's convergence plot, a top view of cameras and points, and
// the view graph of the verified pairs.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "evaluation/evaluation.h"
#include "pgba/scene/reconstruction.h"
#include "report/view_graph_svg.h"

namespace pgba {

struct HtmlReportInput {
  std::string title;
  const nlohmann::json* report = nullptr;    // report.json (stages with "seconds" and "order")
  const Reconstruction* model = nullptr;     // the final model
  // Every model, largest first, for the 3D view (null: `model` alone; neither: no 3D view).
  const std::vector<const Reconstruction*>* models = nullptr;
  const std::vector<double>* convergence = nullptr;  // sigma per iteration (may be empty)
  // Tracks the convergence curve was evaluated on, of all (a sample when fewer; 0: not said).
  size_t convergence_tracks = 0, convergence_tracks_total = 0;
  const EvaluationMetrics* metrics = nullptr;        // of the final model (may be null)
  const ViewGraphPicture* view_graph = nullptr;      // the front end's verified pairs (may be null)
};

std::string RunReportHtml(const HtmlReportInput& input);

// Top view: camera centres and points projected on the plane of the two principal axes of
// the camera centres and points (points beyond the 2nd..98th percentiles are left out so a
// few far points do not shrink the picture).
std::string TopViewSvg(const Reconstruction& model, int width = 640, int height = 480);

}  // namespace pgba
