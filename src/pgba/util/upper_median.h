// The robust scale of the estimators (averaging, triplets, global BA): the element at
// position n/2 of the sorted values, i.e. the upper of the two middle ones for an even count,
// found by partial sorting; 0 for no values. The evaluation's metrics use their own Median
// (evaluation/statistics.h: the mean of the two middle ones, NaN when empty), so that a
// table's "median" means what statisticians mean by it.
#pragma once

#include <algorithm>
#include <vector>

namespace pgba {

inline double UpperMedian(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

}  // namespace pgba
