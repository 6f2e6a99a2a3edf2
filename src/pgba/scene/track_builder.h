// Tracks from pairwise feature matches: union-find over (image, feature) nodes, one track
// per connected component. Shared by the image front end (verified matches of our own
// features) and the COLMAP database import (COLMAP's verified matches).
//
// A component holding two different features of one image is inconsistent (some match in
// it is wrong, or two nearby features were both matched); such tracks are dropped whole
// rather than split, because which observation is wrong cannot be told from the matches
// alone and a wrong track biases every adjustment downstream. They are counted in the stats.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "pgba/scene/reconstruction.h"

namespace pgba {

// The keypoints of one image (pixels, COLMAP convention) before tracks exist.
struct KeypointImage {
  uint32_t image_id = 0;
  std::string name;
  uint32_t camera_id = 0;
  std::vector<Eigen::Vector2d> keypoints;
};

// Matches between two images, as feature indices (idx in image 1, idx in image 2).
struct PairMatches {
  uint32_t image_id1 = 0;
  uint32_t image_id2 = 0;
  std::vector<std::pair<uint32_t, uint32_t>> matches;
};

struct TrackBuilderOptions {
  // Tracks seen in fewer images are dropped (2 keeps every verified match).
  int min_track_length = 2;
  // Empty when valid, else one line naming the first field out of its valid range (the
  // ranges of io/option_ranges.cc) or breaking a rule between fields.
  std::string Check() const;
};
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(TrackBuilderOptions, min_track_length)

struct TrackStats {
  size_t num_tracks = 0;
  size_t num_observations = 0;
  size_t num_conflicting = 0;  // components dropped for holding two features of one image
  size_t num_short = 0;        // components shorter than min_track_length
  double mean_track_length = 0.0;
};

// Builds the tracks model: every input image (with its camera), points2D = the keypoints
// that belong to a kept track (in feature-index order), points3D = the tracks (xyz = 0,
// elements ordered by image id). Point ids are 1..n in the order of each track's smallest
// (image id, feature index), so the output does not depend on the order of `pairs`.
// Throws InputError for a match naming an unknown image or an out-of-range feature index
// (`source` names the input in the message).
Reconstruction BuildTracks(const std::map<uint32_t, Camera>& cameras, const std::vector<KeypointImage>& images,
                           const std::vector<PairMatches>& pairs, const TrackBuilderOptions& options,
                           TrackStats* stats = nullptr, const std::string& source = "matches");

}  // namespace pgba
