// One-dimensional minimisation without derivatives for the calibration's small searches
// (a focal factor, a k1): a grid over the whole interval, so that a cost with several local
// minima is not caught in the wrong one, then a golden-section search (Press et al.,
// Numerical Recipes, 3rd ed., 10.2) between the neighbours of the best node.
#pragma once

#include <algorithm>
#include <cmath>

namespace pgba {

struct GridMinimum {
  double x = 0.0;
  double cost = 0.0;
  bool at_bound = false;  // the best node is an end of the interval
};

// Minimises f over [lo, hi] with `nodes` >= 3 evenly spaced evaluations, then golden-section
// iterations until the bracket is narrower than `tolerance`; returns the refined point, or
// the best node if that is lower (f need not be unimodal within the bracket).
template <typename F>
GridMinimum MinimiseByGridAndGoldenSection(const F& f, double lo, double hi, int nodes, double tolerance) {
  const double step = (hi - lo) / (nodes - 1);
  int best = 0;
  double best_cost = INFINITY;
  for (int k = 0; k < nodes; ++k) {
    const double c = f(lo + step * k);
    if (c < best_cost) {
      best_cost = c;
      best = k;
    }
  }
  double a = lo + step * std::max(0, best - 1), b = lo + step * std::min(nodes - 1, best + 1);
  const double g = 0.5 * (std::sqrt(5.0) - 1.0);
  double c = b - g * (b - a), d = a + g * (b - a);
  double fc = f(c), fd = f(d);
  while (b - a > tolerance) {
    if (fc < fd) {
      b = d;
      d = c;
      fd = fc;
      c = b - g * (b - a);
      fc = f(c);
    } else {
      a = c;
      c = d;
      fc = fd;
      d = a + g * (b - a);
      fd = f(d);
    }
  }
  GridMinimum m;
  m.at_bound = best == 0 || best == nodes - 1;
  m.x = 0.5 * (a + b);
  m.cost = f(m.x);
  if (!(m.cost <= best_cost)) {
    m.x = lo + step * best;
    m.cost = best_cost;
  }
  return m;
}

}  // namespace pgba
