// The per-image feature cache WS/features/<image name>.bin: a small binary format with a
// header, so a re-run can tell a finished image from a stale or damaged one.
//
// Layout (little-endian):
//   char[8]  "PGBAFEAT"
//   uint32   version (kFeatureFileVersion)
//   uint32   key length, then the key bytes (extraction options + source file signature)
//   int32    width, height (full-resolution image size)
//   float32  the contrast threshold detection ended at (FeatureSet::contrast_threshold)
//   uint32   number of keypoints n, descriptor size d
//   float32  n x 4 keypoints (x, y, scale, orientation)
//   uint8    n x d descriptors
//   char[4]  "END."
//   uint64   FNV-1a 64 of every byte before it (util/checksum.h)
// Files are written atomically (temporary + rename), so a killed run leaves no half file;
// the checksum catches the damage that keeps the size (a flipped bit), which the header and
// trailer checks alone let through as silently wrong keypoints or descriptors.
#pragma once

#include <string>

#include "features/feature_set.h"

namespace pgba {

constexpr uint32_t kFeatureFileVersion = 3;  // 2: checksum, 3: contrast threshold used

void WriteFeatureFile(const std::string& path, const FeatureSet& features, const std::string& key);

// Reads a feature file; `key` (optional) receives the stored key. A missing, truncated,
// damaged (checksum) or malformed file is an InputError naming the file and the problem.
FeatureSet ReadFeatureFile(const std::string& path, std::string* key = nullptr);

// The checksum stored at the end of a feature file (its last 8 bytes): a hash of its whole
// content, which holds the hash of the source photo (the key), so the caches downstream of
// the features (the tracks) are keyed on the photos' content through it. InputError naming
// the file if it is missing or too short.
uint64_t FeatureFileChecksum(const std::string& path);

}  // namespace pgba
