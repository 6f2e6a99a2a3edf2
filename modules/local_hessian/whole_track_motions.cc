#include "modules/local_hessian/whole_track_motions.h"

#include <algorithm>
#include <set>
#include <tuple>

namespace pgba {

namespace {

struct TrackViews {
  uint64_t track_id = 0;
  std::vector<uint32_t> views;  // posed images seeing the track, ascending, each once
  int observations = 0;
};

struct MotionBuild {
  std::set<uint32_t> views;
  std::vector<size_t> tracks;  // indices into the TrackViews list
  long observations = 0;
  bool alive = true;
};

class Assigner {
 public:
  Assigner(const std::vector<TrackViews>& tracks, const WholeTrackMotionOptions& options)
      : tracks_(tracks), options_(options) {}

  // Puts track t into the best motion among `candidates` (anchors); false if none is usable.
  bool Assign(size_t t, const std::vector<uint32_t>& candidates) {
    const TrackViews& tv = tracks_[t];
    bool found = false;
    std::tuple<bool, size_t, long, uint32_t> best;
    for (const uint32_t a : candidates) {
      const auto it = motions_.find(a);
      const MotionBuild* m = it == motions_.end() ? nullptr : &it->second;
      if (m && !m->alive) continue;
      size_t added = 0;
      for (const uint32_t v : tv.views) added += !m || !m->views.count(v);
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
    for (const uint32_t v : tracks_[t].views)
      if (m.views.insert(v).second) containing_[v].insert(anchor);
    m.tracks.push_back(t);
    m.observations += tracks_[t].observations;
  }

  // Alive, non-empty motions containing at least one view of track t, other than `except`.
  std::vector<uint32_t> MotionsTouching(size_t t, uint32_t except) const {
    std::set<uint32_t> out;
    for (const uint32_t v : tracks_[t].views)
      if (const auto it = containing_.find(v); it != containing_.end())
        for (const uint32_t a : it->second)
          if (a != except && motions_.at(a).alive) out.insert(a);
    return {out.begin(), out.end()};
  }

  // Dissolves motions with fewer than min_tracks tracks, smallest first, while their tracks
  // can all move to other motions.
  void DissolveSmallMotions() {
    std::set<uint32_t> kept_small;  // could not be dissolved
    for (;;) {
      uint32_t victim = 0;
      size_t fewest = 0;
      bool any = false;
      for (const auto& [a, m] : motions_)
        if (m.alive && !m.tracks.empty() && static_cast<int>(m.tracks.size()) < options_.min_tracks &&
            !kept_small.count(a) && (!any || m.tracks.size() < fewest))
          victim = a, fewest = m.tracks.size(), any = true;
      if (!any) return;
      MotionBuild& m = motions_.at(victim);
      std::vector<std::vector<uint32_t>> targets;
      bool movable = true;
      for (const size_t t : m.tracks) {
        targets.push_back(MotionsTouching(t, victim));
        movable = movable && !targets.back().empty();
      }
      if (!movable) {
        kept_small.insert(victim);
        continue;
      }
      m.alive = false;
      const std::vector<size_t> moved = std::move(m.tracks);
      m.tracks.clear();
      for (const uint32_t v : m.views) containing_[v].erase(victim);
      for (size_t i = 0; i < moved.size(); ++i) Assign(moved[i], targets[i]);
    }
  }

  const std::map<uint32_t, MotionBuild>& motions() const { return motions_; }

 private:
  const std::vector<TrackViews>& tracks_;
  const WholeTrackMotionOptions& options_;
  std::map<uint32_t, MotionBuild> motions_;           // by anchor image
  std::map<uint32_t, std::set<uint32_t>> containing_;  // image -> anchors of the motions holding it
};

}  // namespace

std::vector<LocalMotion> SelectWholeTrackMotions(const Reconstruction& tracks, const std::map<uint32_t, Pose>& poses,
                                                 const WholeTrackMotionOptions& options) {
  std::vector<TrackViews> list;
  for (const auto& [track_id, point] : tracks.points3D) {
    TrackViews tv;
    tv.track_id = track_id;
    for (const TrackElement& el : point.track)
      if (poses.count(el.image_id)) tv.views.push_back(el.image_id);
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

  Assigner assigner(list, options);
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
  for (const auto& [anchor, m] : assigner.motions()) {
    if (!m.alive || m.tracks.empty() || m.views.size() < 2) continue;
    LocalMotion lm;
    lm.image_ids.assign(m.views.begin(), m.views.end());
    for (const uint32_t id : lm.image_ids) lm.local_poses.push_back(poses.at(id));
    for (const size_t t : m.tracks) lm.track_ids.push_back(list[t].track_id);
    std::sort(lm.track_ids.begin(), lm.track_ids.end());
    motions.push_back(std::move(lm));
  }
  return motions;
}

}  // namespace pgba
