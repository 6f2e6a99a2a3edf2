// Seeds of independent random streams (one per texture, per image's noise) derived from the
// scene seed and an index: splitmix64's finaliser, so that neighbouring indices give
// unrelated streams and the result depends on nothing but (seed, index), not on the order
// in which threads ask for them.
#pragma once

#include <cstdint>

namespace pgba::synthetic {

inline uint64_t MixSeed(uint64_t a, uint64_t b) {
  uint64_t s = a * 0x9E3779B97F4A7C15ULL + b + 0x632BE59BD9B4E019ULL;
  s = (s ^ (s >> 30)) * 0xBF58476D1CE4E5B9ULL;
  s = (s ^ (s >> 27)) * 0x94D049BB133111EBULL;
  return s ^ (s >> 31);
}

}  // namespace pgba::synthetic
