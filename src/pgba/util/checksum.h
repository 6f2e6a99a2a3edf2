// A 64-bit FNV-1a hash: the checksum of the feature cache files and the fingerprint of a
// workspace's inputs. Not cryptographic: it detects damage and mix-ups, not tampering.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace pgba {

constexpr uint64_t kFnv1a64Offset = 14695981039346656037ull;

// Hash of `size` bytes, continuing from `hash` (chain calls to hash several pieces).
inline uint64_t Fnv1a64(const void* data, size_t size, uint64_t hash = kFnv1a64Offset) {
  const unsigned char* p = static_cast<const unsigned char*>(data);
  for (size_t i = 0; i < size; ++i) {
    hash ^= p[i];
    hash *= 1099511628211ull;
  }
  return hash;
}

inline uint64_t Fnv1a64(const std::string& s, uint64_t hash = kFnv1a64Offset) {
  return Fnv1a64(s.data(), s.size(), hash);
}

// 16 lowercase hex digits.
std::string Hex64(uint64_t value);

}  // namespace pgba
