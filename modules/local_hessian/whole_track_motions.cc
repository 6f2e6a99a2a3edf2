#include "modules/local_hessian/whole_track_motions.h"
#include "pgba/io/option_ranges.h"

#include <algorithm>
#include <tuple>
#include <unordered_map>

namespace pgba {

namespace {

// Images are numbered 0..M-1 in id order (the order of `poses`), so that the selection runs on
// flat arrays: with std::map / std::set per motion it would be a quarter of the pointless
// BA's preparation. Every tie below breaks by that index, i.e. by image id.
struct TrackViews {
  uint64_t track_id = 0;
  std::vector<uint32_t> views;  // indices of the posed images seeing the track, ascending, each once
  int observations = 0;
};

// Inserts v into the ascending vector `sorted`; false if it is there already.
bool InsertSorted(std::vector<uint32_t>* sorted, uint32_t v) {
  const auto it = std::lower_bound(sorted->begin(), sorted->end(), v);
  if (it != sorted->end() && *it == v) return false;
  sorted->insert(it, v);
  return true;
}

bool ContainsSorted(const std::vector<uint32_t>& sorted, uint32_t v) {
  return std::binary_search(sorted.begin(), sorted.end(), v);
}

struct MotionBuild {
  bool exists = false;          // some track was ever added to the motion of this anchor
  std::vector<uint32_t> views;  // ascending image indices
  std::vector<size_t> tracks;   // indices into the TrackViews list
  long observations = 0;
  bool alive = true;
};

class Assigner {
 public:
  Assigner(const std::vector<TrackViews>& tracks, size_t num_images, const WholeTrackMotionOptions& options)
      : tracks_(tracks), options_(options), motions_(num_images), containing_(num_images) {}

  // Puts track t into the best motion among `candidates` (anchors); false if none is usable.
  bool Assign(size_t t, const std::vector<uint32_t>& candidates) {
    const TrackViews& tv = tracks_[t];
    bool found = false;
    std::tuple<bool, size_t, long, uint32_t> best;
    for (const uint32_t a : candidates) {
      const MotionBuild* m = motions_[a].exists ? &motions_[a] : nullptr;
      if (m && !m->alive) continue;
      size_t added = 0;
      for (const uint32_t v : tv.views) added += !m || !ContainsSorted(m->views, v);
      const size_t size = (m ? m->views.size() : 0) + added;
      // A motion may grow to max_views, or to the length of the track itself: a track longer
      // than max_views opens a motion of its own views (size L, never over) instead of
      // chaining every overlapping long track into one motion.
      const bool over = added > 0 && size > std::max<size_t>(options_.max_views, tv.views.size());
      const auto key = std::make_tuple(over, added, m ? m->observations : 0L, a);
      if (!found || key < best) best = key, found = true;
    }
    if (!found) return false;
    Add(std::get<3>(best), t);
    return true;
  }

  void Add(uint32_t anchor, size_t t) {
    MotionBuild& m = motions_[anchor];
    m.exists = true;
    for (const uint32_t v : tracks_[t].views)
      if (InsertSorted(&m.views, v)) InsertSorted(&containing_[v], anchor);
    m.tracks.push_back(t);
    m.observations += tracks_[t].observations;
  }

  // Alive, non-empty motions containing at least one view of track t, other than `except`,
  // ascending.
  std::vector<uint32_t> MotionsTouching(size_t t, uint32_t except) const {
    std::vector<uint32_t> out;
    for (const uint32_t v : tracks_[t].views)
      for (const uint32_t a : containing_[v])
        if (a != except && motions_[a].alive) out.push_back(a);
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
  }

  // Dissolves motions with fewer than min_tracks tracks, smallest first, while their tracks
  // can all move to other motions.
  void DissolveSmallMotions() {
    std::vector<char> kept_small(motions_.size(), 0);  // could not be dissolved
    for (;;) {
      uint32_t victim = 0;
      size_t fewest = 0;
      bool any = false;
      for (uint32_t a = 0; a < motions_.size(); ++a) {
        const MotionBuild& m = motions_[a];
        if (m.exists && m.alive && !m.tracks.empty() && static_cast<int>(m.tracks.size()) < options_.min_tracks &&
            !kept_small[a] && (!any || m.tracks.size() < fewest))
          victim = a, fewest = m.tracks.size(), any = true;
      }
      if (!any) return;
      MotionBuild& m = motions_[victim];
      std::vector<std::vector<uint32_t>> targets;
      bool movable = true;
      for (const size_t t : m.tracks) {
        targets.push_back(MotionsTouching(t, victim));
        movable = movable && !targets.back().empty();
      }
      if (!movable) {
        kept_small[victim] = 1;
        continue;
      }
      m.alive = false;
      const std::vector<size_t> moved = std::move(m.tracks);
      m.tracks.clear();
      for (const uint32_t v : m.views) {
        std::vector<uint32_t>& c = containing_[v];
        c.erase(std::remove(c.begin(), c.end(), victim), c.end());
      }
      for (size_t i = 0; i < moved.size(); ++i) Assign(moved[i], targets[i]);
    }
  }

  // Indexed by anchor image; entries with exists = false were never used.
  const std::vector<MotionBuild>& motions() const { return motions_; }

 private:
  const std::vector<TrackViews>& tracks_;
  const WholeTrackMotionOptions& options_;
  std::vector<MotionBuild> motions_;                // by anchor image index
  std::vector<std::vector<uint32_t>> containing_;  // image index -> anchors of the motions holding it, ascending
};

}  // namespace

std::vector<LocalMotion> SelectWholeTrackMotions(const Reconstruction& tracks, const std::map<uint32_t, Pose>& poses,
                                                 const WholeTrackMotionOptions& options) {
  std::vector<uint32_t> image_id;  // index -> id, ascending
  std::unordered_map<uint32_t, uint32_t> index_of;
  for (const auto& [id, pose] : poses) {
    index_of.emplace(id, static_cast<uint32_t>(image_id.size()));
    image_id.push_back(id);
  }
  std::vector<TrackViews> list;
  for (const auto& [track_id, point] : tracks.points3D) {
    TrackViews tv;
    tv.track_id = track_id;
    for (const TrackElement& el : point.track)
      if (const auto it = index_of.find(el.image_id); it != index_of.end()) tv.views.push_back(it->second);
    std::sort(tv.views.begin(), tv.views.end());
    tv.views.erase(std::unique(tv.views.begin(), tv.views.end()), tv.views.end());
    tv.observations = static_cast<int>(tv.views.size());
    if (tv.views.size() >= 2) list.push_back(std::move(tv));
  }
  // Longest first: long tracks lay out the windows, shorter ones then fall inside them.
  std::vector<size_t> order(list.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return list[a].views.size() > list[b].views.size(); });

  Assigner assigner(list, image_id.size(), options);
  for (const size_t t : order) {
    // Candidates: the motions anchored at the track's views and those already holding one
    // of its views.
    std::vector<uint32_t> candidates = assigner.MotionsTouching(t, /*except=*/~0u);
    candidates.insert(candidates.end(), list[t].views.begin(), list[t].views.end());
    std::sort(candidates.begin(), candidates.end());
    candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
    assigner.Assign(t, candidates);
  }
  assigner.DissolveSmallMotions();

  std::vector<LocalMotion> motions;
  for (const MotionBuild& m : assigner.motions()) {
    if (!m.exists || !m.alive || m.tracks.empty() || m.views.size() < 2) continue;
    LocalMotion lm;
    for (const uint32_t v : m.views) lm.image_ids.push_back(image_id[v]);
    for (const uint32_t id : lm.image_ids) lm.local_poses.push_back(poses.at(id));
    for (const size_t t : m.tracks) lm.track_ids.push_back(list[t].track_id);
    std::sort(lm.track_ids.begin(), lm.track_ids.end());
    motions.push_back(std::move(lm));
  }
  return motions;
}

std::string WholeTrackMotionOptions::Check() const {
  return CheckRangesAt({{"max_views", max_views}, {"min_tracks", min_tracks}}, "WholeTrackMotionOptions");
}

}  // namespace pgba
