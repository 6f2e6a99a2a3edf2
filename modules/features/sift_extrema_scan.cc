#include "features/sift_extrema_scan.h"

#include <cstdint>

#include "features/vec8.h"

namespace pgba {
namespace {

// Inline only, no vector crosses a call boundary; GCC reports it at the end of the file.
#pragma GCC diagnostic ignored "-Wpsabi"
using simd::Bits8;
using simd::Load8;
using simd::Vec8;
using simd::Vec8i;

// The same test as the vector one, for one column.
inline bool IsExtremum(const float* g0, const float* g1, const float* g2, const float* g3, std::ptrdiff_t step, int c,
                       float pre) {
  const std::ptrdiff_t around[9] = {-step - 1, -step, -step + 1, -1, 0, 1, step - 1, step, step + 1};
  const float v = g2[c] - g1[c];
  if (!(v > pre || v < -pre)) return false;
  for (const std::ptrdiff_t a : around) {
    const float same = g2[c + a] - g1[c + a], below = g1[c + a] - g0[c + a], above = g3[c + a] - g2[c + a];
    if (v > 0 ? (a != 0 && v < same) || v < below || v < above : (a != 0 && v > same) || v > below || v > above)
      return false;
  }
  return true;
}

}  // namespace

PGBA_MULTIVERSION
int ScanDogRowForExtrema(const float* g0, const float* g1, const float* g2, const float* g3, std::ptrdiff_t step,
                         int c_begin, int c_end, float pre, int* cols) {
  // The 8 neighbours in the same layer first (most samples fail there), then 9 + 9.
  const std::ptrdiff_t same[8] = {-step - 1, -step, -step + 1, -1, 1, step - 1, step, step + 1};
  const std::ptrdiff_t all[9] = {-step - 1, -step, -step + 1, -1, 0, 1, step - 1, step, step + 1};
  int count = 0;
  int c = c_begin;
  for (; c + 8 <= c_end; c += 8) {
    const Vec8 v = Load8(g2 + c) - Load8(g1 + c);
    Vec8i hi = v > pre, lo = v < -pre;
    if (Bits8(hi | lo) == 0) continue;
    for (const std::ptrdiff_t a : same) {
      const Vec8 n = Load8(g2 + c + a) - Load8(g1 + c + a);
      hi &= v >= n;
      lo &= v <= n;
    }
    if (Bits8(hi | lo) == 0) continue;
    for (const std::ptrdiff_t a : all) {
      const Vec8 below = Load8(g1 + c + a) - Load8(g0 + c + a);
      const Vec8 above = Load8(g3 + c + a) - Load8(g2 + c + a);
      hi &= (v >= below) & (v >= above);
      lo &= (v <= below) & (v <= above);
    }
    for (uint32_t bits = Bits8(hi | lo); bits != 0; bits &= bits - 1) cols[count++] = c + __builtin_ctz(bits);
  }
  for (; c < c_end; ++c)
    if (IsExtremum(g0, g1, g2, g3, step, c, pre)) cols[count++] = c;
  return count;
}

}  // namespace pgba
