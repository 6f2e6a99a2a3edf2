#include "report/svg_plot.h"

#include "pgba/io/option_ranges.h"
#include "pgba/util/text_format.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

namespace pgba {
namespace {

const char* kColors[] = {"#d62728", "#1f77b4", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b"};

// "Nice" linear ticks covering [lo, hi].
std::vector<double> LinearTicks(double lo, double hi, bool integers = false) {
  const double span = std::max(hi - lo, 1e-12);
  const double raw = span / 5.0;
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  double step = mag;
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * mag >= raw) {
      step = m * mag;
      break;
    }
  if (integers) step = std::max(step, 1.0);
  std::vector<double> ticks;
  for (double t = std::ceil(lo / step) * step; t <= hi + 1e-9 * span; t += step) ticks.push_back(t);
  return ticks;
}

std::vector<AxisTick> LinearAxisTicks(double lo, double hi) {
  std::vector<AxisTick> ticks;
  for (double t : LinearTicks(lo, hi)) ticks.push_back({t, true});
  return ticks;
}

}  // namespace

std::vector<AxisTick> LogTicks(double lo, double hi) {
  std::vector<AxisTick> ticks;
  const int decades = static_cast<int>(std::ceil(hi - lo - 1e-9));
  // 1, 2 and 5 of each decade labelled over up to three decades, the decades alone beyond;
  // the other integers of each decade are unlabelled grid lines.
  const bool label_two_five = decades <= 3;
  for (double e = std::floor(lo + 1e-9); e <= hi + 1e-9; e += 1.0)
    for (int m = 1; m <= 9; ++m) {
      const double t = e + std::log10(static_cast<double>(m));
      if (t < lo - 1e-9 || t > hi + 1e-9) continue;
      ticks.push_back({t, m == 1 || (label_two_five && (m == 2 || m == 5))});
    }
  return ticks;
}

std::string LinePlotSvg(const std::vector<PlotSeries>& series, const PlotOptions& o) {
  auto usable = [&](double y) { return std::isfinite(y) && (!o.log_y || y > 0); };
  double xmin = std::numeric_limits<double>::infinity(), xmax = -xmin, ymin = xmin, ymax = -xmin;
  for (const PlotSeries& s : series)
    for (size_t i = 0; i < std::min(s.x.size(), s.y.size()); ++i) {
      if (!usable(s.y[i]) || !std::isfinite(s.x[i])) continue;
      const double y = o.log_y ? std::log10(s.y[i]) : s.y[i];
      xmin = std::min(xmin, s.x[i]);
      xmax = std::max(xmax, s.x[i]);
      ymin = std::min(ymin, y);
      ymax = std::max(ymax, y);
    }
  if (!std::isfinite(xmin)) xmin = 0, xmax = 1, ymin = 0, ymax = 1;
  if (xmax - xmin < 1e-12) xmax = xmin + 1;
  if (o.log_y) {
    // Whole decades: a tick at each decade, the ends included, whatever the data's span.
    ymin = std::floor(ymin + 1e-9), ymax = std::ceil(ymax - 1e-9);
    if (ymax - ymin < 1.0) ymax = ymin + 1.0;
  }
  if (ymax - ymin < 1e-12) ymin -= 0.5, ymax += 0.5;

  const double left = 70, right = 20, top = 36, bottom = 50;
  const double pw = o.width - left - right, ph = o.height - top - bottom;
  auto px = [&](double x) { return left + (x - xmin) / (xmax - xmin) * pw; };
  auto py = [&](double y) { return top + (1.0 - (y - ymin) / (ymax - ymin)) * ph; };

  std::ostringstream svg;
  svg << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << o.width << "\" height=\"" << o.height
      << "\" font-family=\"sans-serif\" font-size=\"12\">\n"
      << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
      << "<text x=\"" << o.width / 2 << "\" y=\"20\" text-anchor=\"middle\" font-size=\"14\">" << XmlEscape(o.title)
      << "</text>\n"
      << "<rect x=\"" << left << "\" y=\"" << top << "\" width=\"" << pw << "\" height=\"" << ph
      << "\" fill=\"none\" stroke=\"#444\"/>\n";
  for (double t : LinearTicks(xmin, xmax, o.integer_x))
    svg << "<line x1=\"" << px(t) << "\" y1=\"" << top + ph << "\" x2=\"" << px(t) << "\" y2=\"" << top + ph + 5
        << "\" stroke=\"#444\"/><text x=\"" << px(t) << "\" y=\"" << top + ph + 18 << "\" text-anchor=\"middle\">"
        << FormatNumber("%.4g", t) << "</text>\n";
  for (const AxisTick& t : o.log_y ? LogTicks(ymin, ymax) : LinearAxisTicks(ymin, ymax)) {
    svg << "<line x1=\"" << left << "\" y1=\"" << py(t.at) << "\" x2=\"" << left + pw << "\" y2=\"" << py(t.at)
        << "\" stroke=\"" << (t.labelled ? "#ccc" : "#eee") << "\"/>";
    if (t.labelled)
      svg << "<line x1=\"" << left - 5 << "\" y1=\"" << py(t.at) << "\" x2=\"" << left << "\" y2=\"" << py(t.at)
          << "\" stroke=\"#444\"/><text x=\"" << left - 8 << "\" y=\"" << py(t.at) + 4
          << "\" text-anchor=\"end\">" << FormatNumber("%.4g", o.log_y ? std::pow(10.0, t.at) : t.at) << "</text>";
    svg << "\n";
  }
  svg << "<text x=\"" << left + pw / 2 << "\" y=\"" << o.height - 12 << "\" text-anchor=\"middle\">"
      << XmlEscape(o.x_label) << "</text>\n"
      << "<text transform=\"translate(16," << top + ph / 2 << ") rotate(-90)\" text-anchor=\"middle\">"
      << XmlEscape(o.y_label) << (o.log_y ? " (log scale)" : "") << "</text>\n";

  for (size_t k = 0; k < series.size(); ++k) {
    const PlotSeries& s = series[k];
    const char* color = kColors[k % (sizeof(kColors) / sizeof(kColors[0]))];
    std::ostringstream pts;
    int n = 0;
    for (size_t i = 0; i < std::min(s.x.size(), s.y.size()); ++i) {
      if (!usable(s.y[i]) || !std::isfinite(s.x[i])) continue;
      const double x = px(s.x[i]), y = py(o.log_y ? std::log10(s.y[i]) : s.y[i]);
      pts << x << "," << y << " ";
      svg << "<circle cx=\"" << x << "\" cy=\"" << y << "\" r=\"2.5\" fill=\"" << color << "\"/>\n";
      ++n;
    }
    if (n > 1)
      svg << "<polyline fill=\"none\" stroke=\"" << color << "\" stroke-width=\"1.8\" points=\"" << pts.str()
          << "\"/>\n";
    const double ly = top + 14 + 16 * k;
    svg << "<line x1=\"" << left + pw - 130 << "\" y1=\"" << ly << "\" x2=\"" << left + pw - 110 << "\" y2=\"" << ly
        << "\" stroke=\"" << color << "\" stroke-width=\"3\"/><text x=\"" << left + pw - 104 << "\" y=\"" << ly + 4
        << "\">" << XmlEscape(s.name) << "</text>\n";
  }
  svg << "</svg>\n";
  return svg.str();
}

std::string PlotOptions::Check() const {
  return CheckRangesAt({{"width", width}, {"height", height}}, "PlotOptions");
}

}  // namespace pgba
