// Minimal self-contained SVG line plots for the benchmark's figures (paper Figures 3 and 4):
// several named series, linear x, linear or log10 y, axes with ticks and a legend. No
// external plotting library is packaged for C++ on Debian; the SVG subset used here is
// small and renders in every browser.
#pragma once

#include <string>
#include <vector>

namespace pgba {

struct PlotSeries {
  std::string name;
  std::vector<double> x;
  std::vector<double> y;  // non-finite or (log scale) non-positive values are skipped
};

struct PlotOptions {
  std::string title;
  std::string x_label;
  std::string y_label;
  bool log_y = false;
  int width = 640;
  int height = 420;
  // Empty when valid, else one line naming the first field out of its valid range (the
  // ranges of io/option_ranges.cc) or breaking a rule between fields.
  std::string Check() const;
};

// The whole SVG document. Series with no drawable point are listed in the legend only.
std::string LinePlotSvg(const std::vector<PlotSeries>& series, const PlotOptions& options);

}  // namespace pgba
