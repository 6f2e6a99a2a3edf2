// The view graph of report.html: which images the front end connected to which. Images sit
// on a circle in name order (for a ring shot in sequence, its order), one line per verified
// pair, thicker for more inliers; registered images filled, dropped ones hollow red. On an
// object ring it shows at a glance the gaps of the ring and the pairs 2-3 steps apart
// (chords) that bridge them.
#pragma once

#include <string>
#include <vector>

#include "pgba/scene/reconstruction.h"
#include "pgba/scene/view_graph.h"

namespace pgba {

struct ViewGraphPicture {
  struct Image {
    std::string name;
    bool registered = false;
  };
  struct Edge {
    int a = 0, b = 0;  // indices into images
    int inliers = 0;
  };
  std::vector<Image> images;  // in the order drawn around the circle
  std::vector<Edge> edges;
};

// The images of `tracks` in name order, registered when `model` has an image of that name,
// and one edge per pair of `pairs` (image ids of `tracks`).
ViewGraphPicture MakeViewGraphPicture(const Reconstruction& tracks, const std::vector<TwoViewGeometry>& pairs,
                                      const Reconstruction& model);

std::string ViewGraphSvg(const ViewGraphPicture& graph, int size = 420);

// The same graph in words, an HTML table: per image (numbered as in the picture), whether it
// is registered and the images it is connected to, each with its pair's inliers.
std::string ViewGraphTable(const ViewGraphPicture& graph);

}  // namespace pgba
