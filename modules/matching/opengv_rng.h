// Reproducible sampling for OpenGV's sample-consensus problems.
//
// opengv::sac::SampleConsensusProblem draws its samples through the public functor
// rng_gen_, built at construction from a *copy* of its rng_alg_ engine seeded with the
// clock (or 12345): reseeding rng_alg_ afterwards has no effect. Replacing the functor with
// one driven by our own engine makes RANSAC deterministic for a given seed, independent of
// thread scheduling.
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <random>

namespace pgba {

template <typename SacProblem>
void SeedSacProblem(uint64_t seed, SacProblem* problem) {
  auto engine = std::make_shared<std::mt19937>(static_cast<uint32_t>(seed ^ (seed >> 32)));
  problem->rng_gen_ = std::make_shared<std::function<int()>>([engine]() {
    return std::uniform_int_distribution<int>(0, std::numeric_limits<int>::max())(*engine);
  });
}

// SplitMix64 finaliser: decorrelated per-item seeds from a base seed and an item key.
inline uint64_t MixSeed(uint64_t seed, uint64_t key) {
  uint64_t z = seed + 0x9e3779b97f4a7c15ULL * (key + 1);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

}  // namespace pgba
