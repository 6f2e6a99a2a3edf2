// Per-image view of the input tracks: for every image the (track, observation) pairs it
// holds, sorted by track id, so that the tracks shared by two or three images are found by
// merging sorted lists. Built once from the tracks Reconstruction (its poses and point
// coordinates are ignored) and validated on the way.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include "pgba/scene/reconstruction.h"

namespace pgba {

struct TrackObservation {
  uint64_t track_id = 0;
  uint32_t point2D_idx = 0;
};

class TrackIndex {
 public:
  // Throws InputError ("tracks: ...") for a track referring to a missing image or
  // observation, an image without a valid camera, or a non-finite pixel.
  explicit TrackIndex(const Reconstruction& tracks);

  const Reconstruction& tracks() const { return *tracks_; }
  // Observations of an image, sorted by track id, one per track (a track observed twice in
  // the same image keeps its first observation). Empty for an unknown image.
  const std::vector<TrackObservation>& Of(uint32_t image_id) const;
  // Unit bearing and pixel of an observation.
  Eigen::Vector3d Bearing(uint32_t image_id, uint32_t point2D_idx) const;
  const Eigen::Vector2d& Pixel(uint32_t image_id, uint32_t point2D_idx) const;
  const Camera& CameraOf(uint32_t image_id) const;

  // The observations of the tracks both images see, as (point2D_idx in image 1, in image 2),
  // in track order (a merge of the two sorted lists).
  std::vector<std::pair<uint32_t, uint32_t>> SharedObservations(uint32_t image_id1, uint32_t image_id2) const;

  // Number of tracks seen by both images of each pair that shares at least one track,
  // keyed by PairKey(id1 < id2). Walks every track once (cost ~ sum of squared lengths).
  std::map<uint64_t, int> CountSharedTracks() const;

 private:
  const Reconstruction* tracks_;
  std::map<uint32_t, std::vector<TrackObservation>> by_image_;
  std::vector<TrackObservation> empty_;
};

inline uint64_t PairKey(uint32_t a, uint32_t b) {
  return a < b ? (static_cast<uint64_t>(a) << 32) | b : (static_cast<uint64_t>(b) << 32) | a;
}

// A track seen by at least two of three images: point2D index per image (-1 if unseen).
struct TripletTrack {
  uint64_t track_id = 0;
  std::array<int64_t, 3> point2D_idx{{-1, -1, -1}};
  int NumViews() const { return (point2D_idx[0] >= 0) + (point2D_idx[1] >= 0) + (point2D_idx[2] >= 0); }
};

// Tracks seen by >= 2 of the three images, sorted by track id.
std::vector<TripletTrack> TracksOfTriplet(const TrackIndex& index, const std::array<uint32_t, 3>& image_ids);

}  // namespace pgba
