#include "pgba/scene/track_builder.h"

#include <algorithm>
#include <numeric>

#include "pgba/io/option_ranges.h"
#include "pgba/util/error.h"

namespace pgba {
namespace {

// Union-find with path halving and union by size; roots are not canonical, so components
// are keyed afterwards by their smallest node.
class UnionFind {
 public:
  explicit UnionFind(size_t n) : parent_(n), size_(n, 1) { std::iota(parent_.begin(), parent_.end(), size_t(0)); }
  size_t Find(size_t x) {
    while (parent_[x] != x) x = parent_[x] = parent_[parent_[x]];
    return x;
  }
  void Union(size_t a, size_t b) {
    a = Find(a);
    b = Find(b);
    if (a == b) return;
    if (size_[a] < size_[b]) std::swap(a, b);
    parent_[b] = a;
    size_[a] += size_[b];
  }

 private:
  std::vector<size_t> parent_;
  std::vector<size_t> size_;
};

}  // namespace

Reconstruction BuildTracks(const std::map<uint32_t, Camera>& cameras, const std::vector<KeypointImage>& images,
                           const std::vector<PairMatches>& pairs, const TrackBuilderOptions& options, TrackStats* stats,
                           const std::string& source) {
  // Node numbering: images in id order, features consecutive within an image.
  std::vector<const KeypointImage*> sorted;
  for (const KeypointImage& im : images) sorted.push_back(&im);
  std::sort(sorted.begin(), sorted.end(), [](auto* a, auto* b) { return a->image_id < b->image_id; });
  std::map<uint32_t, size_t> slot;  // image id -> index in sorted
  std::vector<size_t> offset(sorted.size() + 1, 0);
  for (size_t k = 0; k < sorted.size(); ++k) {
    if (!slot.emplace(sorted[k]->image_id, k).second)
      ThrowInputError(source, 0, "image id " + std::to_string(sorted[k]->image_id) + " appears twice");
    offset[k + 1] = offset[k] + sorted[k]->keypoints.size();
  }
  const size_t num_nodes = offset.back();

  UnionFind uf(num_nodes);
  std::vector<uint8_t> matched(num_nodes, 0);
  for (const PairMatches& pm : pairs) {
    const auto s1 = slot.find(pm.image_id1), s2 = slot.find(pm.image_id2);
    if (s1 == slot.end() || s2 == slot.end())
      ThrowInputError(
          source, 0,
          "matches of unknown image pair " + std::to_string(pm.image_id1) + "-" + std::to_string(pm.image_id2));
    if (pm.image_id1 == pm.image_id2) ThrowInputError(source, 0, "matches of an image with itself");
    const size_t n1 = sorted[s1->second]->keypoints.size(), n2 = sorted[s2->second]->keypoints.size();
    for (const auto& [a, b] : pm.matches) {
      if (a >= n1 || b >= n2)
        ThrowInputError(source, 0,
                        "match " + std::to_string(a) + "-" + std::to_string(b) + " of pair " +
                            std::to_string(pm.image_id1) + "-" + std::to_string(pm.image_id2) + " is out of range (" +
                            std::to_string(n1) + ", " + std::to_string(n2) + " keypoints)");
      const size_t u = offset[s1->second] + a, v = offset[s2->second] + b;
      matched[u] = matched[v] = 1;
      uf.Union(u, v);
    }
  }

  // Components in order of their smallest node (nodes are visited in increasing order).
  std::vector<size_t> component_of_root(num_nodes, SIZE_MAX);
  std::vector<std::vector<size_t>> components;
  for (size_t u = 0; u < num_nodes; ++u) {
    if (!matched[u]) continue;
    const size_t r = uf.Find(u);
    if (component_of_root[r] == SIZE_MAX) {
      component_of_root[r] = components.size();
      components.emplace_back();
    }
    components[component_of_root[r]].push_back(u);
  }

  Reconstruction rec;
  rec.cameras = cameras;
  // Node -> image slot (offset is sorted: binary search).
  auto slot_of = [&](size_t u) {
    return static_cast<size_t>(std::upper_bound(offset.begin(), offset.end(), u) - offset.begin() - 1);
  };
  TrackStats st;
  std::vector<std::vector<size_t>> kept;
  for (auto& comp : components) {
    // Nodes are sorted, hence grouped by image: a repeated slot means a conflict.
    bool conflict = false;
    for (size_t k = 1; k < comp.size() && !conflict; ++k) conflict = slot_of(comp[k]) == slot_of(comp[k - 1]);
    if (conflict) {
      ++st.num_conflicting;
    } else if (static_cast<int>(comp.size()) < options.min_track_length) {
      ++st.num_short;
    } else {
      kept.push_back(std::move(comp));
    }
  }

  // points2D: the kept features of each image, in feature order.
  std::vector<std::vector<size_t>> features_of(sorted.size());
  for (const auto& comp : kept)
    for (size_t u : comp) features_of[slot_of(u)].push_back(u);
  std::vector<uint32_t> point2D_idx(num_nodes, 0);
  for (size_t k = 0; k < sorted.size(); ++k) {
    const KeypointImage& src = *sorted[k];
    if (!cameras.count(src.camera_id))
      ThrowInputError(source, 0, "image " + src.name + " uses unknown camera " + std::to_string(src.camera_id));
    Image& im = rec.images[src.image_id];
    im.image_id = src.image_id;
    im.name = src.name;
    im.camera_id = src.camera_id;
    std::sort(features_of[k].begin(), features_of[k].end());
    im.points2D.reserve(features_of[k].size());
    for (size_t u : features_of[k]) {
      point2D_idx[u] = static_cast<uint32_t>(im.points2D.size());
      Point2D p;
      p.xy = src.keypoints[u - offset[k]];
      im.points2D.push_back(p);
    }
  }
  for (const auto& comp : kept) {
    std::vector<TrackElement> track;
    track.reserve(comp.size());
    for (size_t u : comp) track.push_back({sorted[slot_of(u)]->image_id, point2D_idx[u]});
    st.num_observations += track.size();
    rec.AddPoint3D(Eigen::Vector3d::Zero(), std::move(track));
  }
  st.num_tracks = kept.size();
  st.mean_track_length = st.num_tracks ? static_cast<double>(st.num_observations) / st.num_tracks : 0.0;
  if (stats) *stats = st;
  return rec;
}

std::string TrackBuilderOptions::Check() const {
  if (const std::string m = CheckRanges(*this, "matching.tracks"); !m.empty()) return m;
  return "";
}

}  // namespace pgba
