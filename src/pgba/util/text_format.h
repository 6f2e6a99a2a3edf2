// Text helpers shared by the printed tables (evaluation, benchmark), SVG plots and HTML report.
#pragma once

#include <string>

namespace pgba {

// `s` with the XML/HTML special characters (< > & ") replaced by their entities.
std::string XmlEscape(const std::string& s);

// printf-style formatting of one number; "n/a" for NaN or infinity (a metric that could
// not be computed).
std::string FormatNumber(const char* format, double v);

}  // namespace pgba
