// The scan for DoG extrema of SIFT's detector, 8 columns at a time: the whole 26-neighbour
// test in vector form, so that only true extrema reach the scalar refinement. The upsampled
// octave of a 6 MP photo has 3 x 25 million samples to test per image.
#pragma once

#include <cstddef>

namespace pgba {

// Extrema in columns [c_begin, c_end) of one row of DoG layer l, given pointers to that row
// of the Gaussian layers l - 1, l, l + 1, l + 2 (DoG layer k = g[k + 1] - g[k], the same float
// subtraction wherever it is taken) with a common row step in floats: the columns c where
// v = DoG_l(c) has |v| > pre and v >= its 26 neighbours (8 in layer l, 9 in l - 1 and
// l + 1) when v > 0, or v <= them when v < 0. Writes them to cols in increasing order (room
// for c_end - c_begin) and returns how many. The rows above and below and the columns
// c_begin - 1 and c_end must exist.
int ScanDogRowForExtrema(const float* g0, const float* g1, const float* g2, const float* g3, std::ptrdiff_t step,
                         int c_begin, int c_end, float pre, int* cols);

}  // namespace pgba
