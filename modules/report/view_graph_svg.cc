#include "report/view_graph_svg.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <sstream>

#include "pgba/util/text_format.h"

namespace pgba {

ViewGraphPicture MakeViewGraphPicture(const Reconstruction& tracks, const std::vector<TwoViewGeometry>& pairs,
                                      const std::vector<const Reconstruction*>& models) {
  std::map<std::string, int> model_of;
  for (size_t m = models.size(); m-- > 0;)
    for (const auto& [id, im] : models[m]->images) model_of[im.name] = static_cast<int>(m);
  std::map<std::string, uint32_t> by_name;
  for (const auto& [id, im] : tracks.images) by_name[im.name] = id;
  ViewGraphPicture g;
  std::map<uint32_t, int> index_of;
  for (const auto& [name, id] : by_name) {
    index_of[id] = static_cast<int>(g.images.size());
    const auto m = model_of.find(name);
    g.images.push_back({name, m == model_of.end() ? -1 : m->second});
  }
  for (const TwoViewGeometry& p : pairs) {
    const auto a = index_of.find(p.image_id1), b = index_of.find(p.image_id2);
    if (a != index_of.end() && b != index_of.end()) g.edges.push_back({a->second, b->second, p.num_inliers});
  }
  return g;
}

const char* ModelColour(int model) {
  static const char* kPalette[] = {"#1f77b4", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b",
                                   "#e377c2", "#17becf", "#bcbd22", "#7f7f7f", "#393b79"};
  return kPalette[model % 10];
}

std::string ViewGraphSvg(const ViewGraphPicture& g, int size) {
  const int n = static_cast<int>(g.images.size());
  const double c = size / 2.0, radius = size / 2.0 - 40;
  const auto x = [&](int i) { return c + radius * std::sin(2 * M_PI * i / std::max(n, 1)); };
  const auto y = [&](int i) { return c - radius * std::cos(2 * M_PI * i / std::max(n, 1)); };
  int max_inliers = 1;
  for (const auto& e : g.edges) max_inliers = std::max(max_inliers, e.inliers);
  std::ostringstream svg;
  svg << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << size << "\" height=\"" << size
      << "\"><rect width=\"100%\" height=\"100%\" fill=\"white\" stroke=\"#444\"/>\n";
  for (const auto& e : g.edges) {
    if (e.a < 0 || e.b < 0 || e.a >= n || e.b >= n) continue;
    // Width 0.5-4 px on a log scale of the inliers: 20 and 2000 inliers both stay visible.
    const double w = 0.5 + 3.5 * std::log1p(e.inliers) / std::log1p(max_inliers);
    const int model = g.images[e.a].model;
    const char* colour = model >= 0 && model == g.images[e.b].model ? ModelColour(model) : "#999999";
    svg << "<line x1=\"" << FormatNumber("%.1f", x(e.a)) << "\" y1=\"" << FormatNumber("%.1f", y(e.a)) << "\" x2=\""
        << FormatNumber("%.1f", x(e.b)) << "\" y2=\"" << FormatNumber("%.1f", y(e.b)) << "\" stroke=\"" << colour << "\" "
        << "stroke-opacity=\"0.7\" stroke-width=\"" << FormatNumber("%.2f", w) << "\"><title>"
        << XmlEscape(g.images[e.a].name + " - " + g.images[e.b].name + ": " + std::to_string(e.inliers) +
                     " inliers")
        << "</title></line>\n";
  }
  for (int i = 0; i < n; ++i) {
    const int m = g.images[i].model;
    const bool r = m >= 0;
    svg << "<circle cx=\"" << FormatNumber("%.1f", x(i)) << "\" cy=\"" << FormatNumber("%.1f", y(i))
        << "\" r=\"6\" fill=\"" << (r ? ModelColour(m) : "white") << "\" stroke=\"" << (r ? ModelColour(m) : "#d62728")
        << "\" stroke-width=\"2\"><title>" << XmlEscape(g.images[i].name)
        << (r ? " (model " + std::to_string(m) + ")" : std::string(" (not registered)"))
        << "</title></circle><text x=\"" << FormatNumber("%.1f", c + (radius + 20) * (x(i) - c) / radius)
        << "\" y=\"" << FormatNumber("%.1f", c + (radius + 20) * (y(i) - c) / radius + 4)
        << "\" font-size=\"10\" text-anchor=\"middle\">" << i + 1 << "</text>\n";
  }
  svg << "</svg>\n";
  return svg.str();
}

std::string ViewGraphTable(const ViewGraphPicture& g) {
  const int n = static_cast<int>(g.images.size());
  std::vector<std::map<int, int>> links(n);  // image -> (neighbour -> inliers), by neighbour
  for (const auto& e : g.edges) {
    if (e.a < 0 || e.b < 0 || e.a >= n || e.b >= n) continue;
    links[e.a][e.b] = e.inliers;
    links[e.b][e.a] = e.inliers;
  }
  std::ostringstream h;
  h << "<table><tr><th>#</th><th>image</th><th>model</th><th>connected to (inliers)</th></tr>\n";
  for (int i = 0; i < n; ++i) {
    h << "<tr><td>" << i + 1 << "</td><td>" << XmlEscape(g.images[i].name) << "</td><td>"
      << (g.images[i].registered() ? std::to_string(g.images[i].model) : std::string("<b>no</b>")) << "</td><td>";
    if (links[i].empty()) h << "<b>none</b>";
    const char* sep = "";
    for (const auto& [j, inliers] : links[i]) {
      h << sep << j + 1 << " (" << inliers << ")";
      sep = ", ";
    }
    h << "</td></tr>\n";
  }
  h << "</table>\n";
  return h.str();
}

}  // namespace pgba
