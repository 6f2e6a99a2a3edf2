// Order statistics and root-mean-square of residual sets, shared by every metric so that
// "median" and "RMS" mean the same thing in every row of the evaluation table.
#pragma once

#include <vector>

namespace pgba {

// Median of the values (mean of the two middle ones for an even count); NaN when empty.
double Median(std::vector<double> values);
// sqrt(mean(v^2)); NaN when empty.
double Rms(const std::vector<double>& values);
// Largest value; NaN when empty.
double Max(const std::vector<double>& values);

}  // namespace pgba
