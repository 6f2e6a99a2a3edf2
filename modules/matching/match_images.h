// The matching stage: workspace features (from `pgba features`) -> verified tracks.
//   1. pair selection (pair_selection.h),
//   2. putative matches per pair (descriptor_matcher.h: cascade hashing, ratio test, mutual check),
//   3. geometric verification per pair (two_view_verification.h: OpenGV 5-point RANSAC),
//   4. tracks: union-find over the verified inliers (scene/track_builder.h).
// The result is the tracks model `pgba init --tracks` reads (points3D at the origin) plus
// the verified two-view geometries for the triplet stage.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "matching/descriptor_matcher.h"
#include "matching/pair_selection.h"
#include "matching/two_view_verification.h"
#include "pgba/scene/reconstruction.h"
#include "pgba/scene/track_builder.h"
#include "pgba/scene/view_graph.h"

namespace pgba {

struct MatchingOptions {
  PairSelectionOptions pairs;
  DescriptorMatchOptions descriptors;
  VerificationOptions verification;
  TrackBuilderOptions tracks;
  // Search structures held in memory at once (~5 MB each at 8192 features with the
  // kd-forest, ~0.5 MB of codes with cascade hashing, which shares the descriptors). Pairs are processed in
  // blocks of images so that each forest is built about once per block it appears in.
  int max_indexed_images = 100;
  // Empty when valid, else one line naming the first field out of its valid range (the
  // ranges of io/option_ranges.cc) or breaking a rule between fields.
  std::string Check() const;
};
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(MatchingOptions, pairs, descriptors, verification, tracks,
                                                max_indexed_images)

// One selected pair's verification outcome, by image name (WS/matching/pairs.txt).
struct PairOutcome {
  std::string name1, name2;
  PairCheck check;
};

struct MatchingResult {
  Reconstruction tracks;
  std::vector<TwoViewGeometry> two_view_geometries;  // verified pairs, by (image_id1, image_id2)
  TrackStats track_stats;
  size_t num_pairs = 0;     // selected pairs
  size_t num_putative = 0;  // putative matches over all pairs
  size_t num_verified_matches = 0;
  std::vector<std::string> images_without_tracks;
  std::vector<PairOutcome> pair_outcomes;  // every selected pair, in selection order
  double seconds = 0.0;           // wall time of the stage
  double seconds_matching = 0.0;  // wall time of descriptor matching + verification
  // Thread time summed over pairs (excluding building the per-image search structures).
  double thread_seconds_descriptors = 0.0;
  double thread_seconds_verification = 0.0;
  // CPU time (user + system) of the same: the process' over the pair loop, and each pair's
  // thread's over its two steps (a shared machine's load stretches the wall times above,
  // hardly these).
  double cpu_seconds_matching = 0.0;
  double cpu_seconds_descriptors = 0.0;
  double cpu_seconds_verification = 0.0;
  std::string descriptor_method;
};

// InputError if the workspace has no features (run `pgba features`), fewer than two
// images, or an unreadable feature file. Deterministic whatever the number of threads.
MatchingResult MatchImages(const std::string& workspace, const MatchingOptions& options);

// WS/tracks/ (COLMAP text model), WS/matching/two_view_geometries.txt and
// WS/matching/pairs.txt (every selected pair: putative matches, inliers, rotation sd, verdict).
void WriteMatchingResult(const std::string& workspace, const MatchingResult& result);

// The stage's records in report.json (`pgba match` and `pgba run`): the tracks' counts, and
// those plus the pairs, matches and timing of a matching run.
nlohmann::json TrackRecord(const Reconstruction& tracks, const TrackStats& stats);
nlohmann::json MatchingRecord(const MatchingResult& result);

}  // namespace pgba
