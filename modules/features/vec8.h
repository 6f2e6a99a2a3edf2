// Eight floats as one explicit vector (GCC vector extensions) and the attribute that compiles
// a function twice, for AVX2 and the SSE2 baseline, chosen at run time. The kernels of
// pgba's SIFT use plain IEEE float operations in a fixed order (never reassociated, never
// fused: neither target enables FMA), so both paths and the scalar tails give the same bits.
// GCC's auto-vectoriser fell back to scalar code on the blurs' row-pointer alias checks;
// these are written out instead. Include only in .cc files (the vectors stay inline).
#pragma once

#include <xmmintrin.h>

#include <cstdint>
#include <cstring>

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(__SANITIZE_ADDRESS__)
#define PGBA_MULTIVERSION __attribute__((target_clones("avx2", "default")))
#else
#define PGBA_MULTIVERSION
#endif

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"  // inline only: no vector crosses a call boundary

namespace pgba {
namespace simd {

// On the baseline path a Vec8 is two SSE registers, on the AVX2 one a ymm.
typedef float Vec8 __attribute__((vector_size(32)));
typedef int32_t Vec8i __attribute__((vector_size(32)));

inline __attribute__((always_inline)) Vec8 Load8(const float* p) {
  Vec8 v;
  std::memcpy(&v, p, sizeof(v));
  return v;
}
inline __attribute__((always_inline)) void Store8(float* p, Vec8 v) { std::memcpy(p, &v, sizeof(v)); }
inline __attribute__((always_inline)) Vec8 Splat8(float x) { return Vec8{} + x; }
// |v| by clearing the sign bit (std::abs's result, -0 included).
inline __attribute__((always_inline)) Vec8 Abs8(Vec8 v) {
  return reinterpret_cast<Vec8>(reinterpret_cast<Vec8i>(v) & 0x7fffffff);
}

// Operations without a vector-extension operator, on the two SSE halves of the vector:
// the same instructions on both paths (VEX-encoded on the AVX2 one).
inline __attribute__((always_inline)) void SplitHalves(const void* v, __m128* lo, __m128* hi) {
  std::memcpy(lo, v, sizeof(*lo));
  std::memcpy(hi, static_cast<const char*>(v) + sizeof(*lo), sizeof(*hi));
}
// IEEE square root of each lane.
inline __attribute__((always_inline)) Vec8 Sqrt8(Vec8 v) {
  __m128 lo, hi;
  SplitHalves(&v, &lo, &hi);
  lo = _mm_sqrt_ps(lo);
  hi = _mm_sqrt_ps(hi);
  Vec8 r;
  std::memcpy(&r, &lo, sizeof(lo));
  std::memcpy(reinterpret_cast<char*>(&r) + sizeof(lo), &hi, sizeof(hi));
  return r;
}
// Bit k set when lane k of the comparison result m is set.
inline __attribute__((always_inline)) uint32_t Bits8(Vec8i m) {
  __m128 lo, hi;
  SplitHalves(&m, &lo, &hi);
  return static_cast<uint32_t>(_mm_movemask_ps(lo)) | static_cast<uint32_t>(_mm_movemask_ps(hi)) << 4;
}

}  // namespace simd
}  // namespace pgba

#pragma GCC diagnostic pop
