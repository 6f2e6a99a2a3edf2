// The view graph of report.html: which images the front end connected to which. Images sit
// on a circle in name order (for a ring shot in sequence, its order), one line per verified
// pair, thicker for more inliers; registered images filled in their model's colour (a pair
// within a model in that colour, between models or to an image in none grey), dropped ones
// hollow red. On an object ring it shows at a glance the gaps of the ring, the pairs 2-3 steps
// apart (chords) that bridge them and the parts that became models of their own.
#pragma once

#include <string>
#include <vector>

#include "pgba/scene/reconstruction.h"
#include "pgba/scene/view_graph.h"

namespace pgba {

struct ViewGraphPicture {
  struct Image {
    std::string name;
    int model = -1;  // index of the model holding it (0: the largest), -1: in none
    bool registered() const { return model >= 0; }
  };
  struct Edge {
    int a = 0, b = 0;  // indices into images
    int inliers = 0;
  };
  std::vector<Image> images;  // in the order drawn around the circle
  std::vector<Edge> edges;
};

// The images of `tracks` in name order, each in the first of `models` (largest first) that has
// an image of that name, and one edge per pair of `pairs` (image ids of `tracks`).
ViewGraphPicture MakeViewGraphPicture(const Reconstruction& tracks, const std::vector<TwoViewGeometry>& pairs,
                                      const std::vector<const Reconstruction*>& models);

// A model's colour in the view graph and the 3D view: a qualitative palette (the largest model
// blue), repeating after ten.
const char* ModelColour(int model);

std::string ViewGraphSvg(const ViewGraphPicture& graph, int size = 420);

// The same graph in words, an HTML table: per image (numbered as in the picture), its model
// ("no" when in none) and the images it is connected to, each with its pair's inliers.
std::string ViewGraphTable(const ViewGraphPicture& graph);

}  // namespace pgba
