#include "modules/triplets/track_index.h"

#include <algorithm>
#include <string>

#include "pgba/util/error.h"

namespace pgba {
namespace {

[[noreturn]] void Fail(const std::string& problem) { throw InputError("tracks: " + problem); }

}  // namespace

TrackIndex::TrackIndex(const Reconstruction& tracks) : tracks_(&tracks) {
  for (const auto& [id, image] : tracks.images) {
    auto cam = tracks.cameras.find(image.camera_id);
    if (cam == tracks.cameras.end())
      Fail("image " + std::to_string(id) + " refers to missing camera " + std::to_string(image.camera_id));
    const std::string problem = cam->second.Validate();
    if (!problem.empty()) Fail("camera " + std::to_string(image.camera_id) + ": " + problem);
    by_image_[id];
  }
  // std::map iterates tracks in increasing id: every list comes out sorted.
  for (const auto& [pid, point] : tracks.points3D) {
    for (const TrackElement& el : point.track) {
      auto it = tracks.images.find(el.image_id);
      if (it == tracks.images.end())
        Fail("track " + std::to_string(pid) + " refers to missing image " + std::to_string(el.image_id));
      if (el.point2D_idx >= it->second.points2D.size())
        Fail("track " + std::to_string(pid) + " refers to missing observation " + std::to_string(el.point2D_idx) +
             " of image " + std::to_string(el.image_id));
      if (!it->second.points2D[el.point2D_idx].xy.allFinite())
        Fail("non-finite pixel in image " + std::to_string(el.image_id));
      auto& list = by_image_[el.image_id];
      if (!list.empty() && list.back().track_id == pid) continue;  // second observation in the same image
      list.push_back({pid, el.point2D_idx});
    }
  }
}

const std::vector<TrackObservation>& TrackIndex::Of(uint32_t image_id) const {
  auto it = by_image_.find(image_id);
  return it == by_image_.end() ? empty_ : it->second;
}

const Camera& TrackIndex::CameraOf(uint32_t image_id) const {
  return tracks_->CameraOf(tracks_->images.at(image_id));
}

const Eigen::Vector2d& TrackIndex::Pixel(uint32_t image_id, uint32_t point2D_idx) const {
  return tracks_->images.at(image_id).points2D[point2D_idx].xy;
}

Eigen::Vector3d TrackIndex::Bearing(uint32_t image_id, uint32_t point2D_idx) const {
  return CameraOf(image_id).PixelToBearing(Pixel(image_id, point2D_idx));
}

std::vector<std::pair<uint32_t, uint32_t>> TrackIndex::SharedObservations(uint32_t image_id1,
                                                                          uint32_t image_id2) const {
  const std::vector<TrackObservation>& l1 = Of(image_id1);
  const std::vector<TrackObservation>& l2 = Of(image_id2);
  std::vector<std::pair<uint32_t, uint32_t>> shared;
  for (size_t i = 0, j = 0; i < l1.size() && j < l2.size();) {
    if (l1[i].track_id < l2[j].track_id) {
      ++i;
    } else if (l2[j].track_id < l1[i].track_id) {
      ++j;
    } else {
      shared.emplace_back(l1[i++].point2D_idx, l2[j++].point2D_idx);
    }
  }
  return shared;
}

std::map<uint64_t, int> TrackIndex::CountSharedTracks() const {
  std::map<uint64_t, int> counts;
  std::vector<uint32_t> ids;
  for (const auto& [pid, point] : tracks_->points3D) {
    ids.clear();
    for (const TrackElement& el : point.track) ids.push_back(el.image_id);
    std::sort(ids.begin(), ids.end());
    ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
    for (size_t i = 0; i < ids.size(); ++i)
      for (size_t j = i + 1; j < ids.size(); ++j) ++counts[PairKey(ids[i], ids[j])];
  }
  return counts;
}

std::vector<TripletTrack> TracksOfTriplet(const TrackIndex& index, const std::array<uint32_t, 3>& image_ids) {
  // Three-way merge of the sorted per-image lists.
  const std::vector<TrackObservation>* lists[3] = {&index.Of(image_ids[0]), &index.Of(image_ids[1]),
                                                   &index.Of(image_ids[2])};
  size_t pos[3] = {0, 0, 0};
  std::vector<TripletTrack> out;
  while (true) {
    uint64_t next = UINT64_MAX;
    bool any = false;
    for (int v = 0; v < 3; ++v) {
      if (pos[v] < lists[v]->size()) {
        next = std::min(next, (*lists[v])[pos[v]].track_id);
        any = true;
      }
    }
    if (!any) break;
    TripletTrack t;
    t.track_id = next;
    for (int v = 0; v < 3; ++v) {
      if (pos[v] < lists[v]->size() && (*lists[v])[pos[v]].track_id == next) {
        t.point2D_idx[v] = (*lists[v])[pos[v]].point2D_idx;
        ++pos[v];
      }
    }
    if (t.NumViews() >= 2) out.push_back(t);
  }
  return out;
}

}  // namespace pgba
