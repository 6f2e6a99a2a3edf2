// Minimal self-contained SVG line plots for the benchmark's figures (paper Figures 3 and 4)
// and report.html: several named series, linear x, linear or log10 y (whole decades, a
// labelled tick at each), axes with ticks and a legend. No external plotting library is
// packaged for C++ on Debian; the SVG subset used here is small and renders in every browser.
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
  // x is a count (iterations): ticks on whole numbers only.
  bool integer_x = false;
  int width = 640;
  int height = 420;
  // Empty when valid, else one line naming the first field out of its valid range (the
  // ranges of io/option_ranges.cc) or breaking a rule between fields.
  std::string Check() const;
};

// A tick of the y axis at `at` (log10 of the value on a log axis), labelled or a grid line.
struct AxisTick {
  double at = 0.0;
  bool labelled = false;
};
// The ticks of a log10 axis over [lo, hi] (whole decades, as LinePlotSvg draws it): one at
// every integer multiple of each decade, labelled at each decade and, over up to three
// decades, at 2 and 5 as well.
std::vector<AxisTick> LogTicks(double lo, double hi);

// The whole SVG document. Series with no drawable point are listed in the legend only.
std::string LinePlotSvg(const std::vector<PlotSeries>& series, const PlotOptions& options);

}  // namespace pgba
