#include "modules/triplets/triplet_selection.h"

#include <algorithm>
#include <deque>
#include <map>
#include <numeric>

#include "modules/triplets/track_index.h"

namespace pgba {
namespace {

class UnionFind {
 public:
  explicit UnionFind(size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0); }
  size_t Find(size_t x) {
    while (parent_[x] != x) x = parent_[x] = parent_[parent_[x]];
    return x;
  }
  void Union(size_t a, size_t b) {
    a = Find(a);
    b = Find(b);
    if (a != b) parent_[std::max(a, b)] = std::min(a, b);
  }

 private:
  std::vector<size_t> parent_;
};

std::array<uint64_t, 3> Edges(const std::array<uint32_t, 3>& t) {
  return {PairKey(t[0], t[1]), PairKey(t[0], t[2]), PairKey(t[1], t[2])};
}

// Triplet adjacency through shared pairs, over `members` (indices into `triplets`); each
// neighbour list sorted by the given rank so that searches are deterministic and prefer
// good triplets.
struct TripletGraph {
  std::map<uint64_t, std::vector<size_t>> by_edge;
  template <typename Rank>
  TripletGraph(const std::vector<std::array<uint32_t, 3>>& triplets, const std::vector<size_t>& members, Rank rank) {
    for (size_t i : members)
      for (uint64_t e : Edges(triplets[i])) by_edge[e].push_back(i);
    for (auto& [e, list] : by_edge) std::sort(list.begin(), list.end(), [&](size_t a, size_t b) { return rank(a) < rank(b); });
  }
};

// Union-find over `members` joined through shared pairs.
UnionFind Components(const std::vector<std::array<uint32_t, 3>>& triplets, const std::vector<size_t>& members) {
  UnionFind uf(triplets.size());
  std::map<uint64_t, size_t> first;
  for (size_t i : members) {
    for (uint64_t e : Edges(triplets[i])) {
      auto [it, inserted] = first.emplace(e, i);
      if (!inserted) uf.Union(it->second, i);
    }
  }
  return uf;
}

}  // namespace

std::vector<int> TripletGraphComponents(const std::vector<std::array<uint32_t, 3>>& triplets, int* num_components) {
  std::vector<size_t> all(triplets.size());
  std::iota(all.begin(), all.end(), 0);
  UnionFind uf = Components(triplets, all);
  std::vector<int> label(triplets.size(), -1);
  std::map<size_t, int> root_label;
  for (size_t i = 0; i < triplets.size(); ++i) {
    auto [it, inserted] = root_label.emplace(uf.Find(i), static_cast<int>(root_label.size()));
    label[i] = it->second;
  }
  if (num_components) *num_components = static_cast<int>(root_label.size());
  return label;
}

std::vector<size_t> SelectTriplets(const std::vector<TripletCandidate>& candidates, int max_per_image) {
  const size_t n = candidates.size();
  std::vector<std::array<uint32_t, 3>> triplets(n);
  std::vector<size_t> available;
  for (size_t i = 0; i < n; ++i) {
    triplets[i] = candidates[i].image_ids;
    if (!candidates[i].excluded) available.push_back(i);
  }
  std::vector<uint8_t> selected(n, 0);
  if (max_per_image <= 0) {
    return available;
  }
  // 1. Best first; ties by image ids (deterministic).
  std::vector<size_t> order = available;
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    if (candidates[a].score != candidates[b].score) return candidates[a].score > candidates[b].score;
    return candidates[a].image_ids < candidates[b].image_ids;
  });
  std::vector<size_t> rank(n, 0);
  for (size_t r = 0; r < order.size(); ++r) rank[order[r]] = r;

  // 2. Greedy cap per image.
  std::map<uint32_t, int> count;
  for (size_t i : order) {
    if (!candidates[i].locked) continue;
    selected[i] = 1;
    for (uint32_t v : triplets[i]) ++count[v];
  }
  for (size_t i : order) {
    const auto& t = triplets[i];
    if (selected[i]) continue;
    if (count[t[0]] < max_per_image || count[t[1]] < max_per_image || count[t[2]] < max_per_image) {
      selected[i] = 1;
      for (uint32_t v : t) ++count[v];
    }
  }

  // 3. Connectivity repair within each component of the candidate graph.
  const TripletGraph graph(triplets, available, [&](size_t i) { return rank[i]; });
  UnionFind full = Components(triplets, available);
  while (true) {
    std::vector<size_t> chosen;
    for (size_t i : order)
      if (selected[i]) chosen.push_back(i);
    UnionFind sel = Components(triplets, chosen);
    // Selected sub-components per full component: size and best rank.
    std::map<size_t, std::map<size_t, size_t>> subs;  // full root -> (sel root -> size)
    for (size_t i : chosen) ++subs[full.Find(i)][sel.Find(i)];
    bool repaired = false;
    for (const auto& [froot, parts] : subs) {
      if (parts.size() < 2) continue;
      // Grow from the largest selected component (ties: the one with the smallest root).
      size_t main_root = parts.begin()->first, main_size = 0;
      for (const auto& [root, size] : parts)
        if (size > main_size) main_root = root, main_size = size;
      // 0-1 BFS: selected triplets of the main component cost 0, unselected ones 1.
      std::vector<size_t> dist(n, SIZE_MAX), parent(n, SIZE_MAX);
      std::deque<size_t> queue;
      for (size_t i : chosen)
        if (sel.Find(i) == main_root && full.Find(i) == froot) dist[i] = 0, queue.push_back(i);
      size_t target = SIZE_MAX;
      while (!queue.empty() && target == SIZE_MAX) {
        const size_t cur = queue.front();
        queue.pop_front();
        for (uint64_t e : Edges(triplets[cur])) {
          for (size_t nb : graph.by_edge.at(e)) {
            if (selected[nb] && sel.Find(nb) != main_root) {
              parent[nb] = cur;
              target = nb;
              break;
            }
            const size_t w = selected[nb] ? 0 : 1;
            if (dist[cur] + w < dist[nb]) {
              dist[nb] = dist[cur] + w;
              parent[nb] = cur;
              w == 0 ? queue.push_front(nb) : queue.push_back(nb);
            }
          }
          if (target != SIZE_MAX) break;
        }
      }
      if (target == SIZE_MAX) continue;  // cannot happen inside one full component
      for (size_t cur = parent[target]; cur != SIZE_MAX && dist[cur] > 0; cur = parent[cur]) selected[cur] = 1;
      repaired = true;
      break;  // recompute the components
    }
    if (!repaired) break;
  }
  std::vector<size_t> result;
  for (size_t i = 0; i < n; ++i)
    if (selected[i]) result.push_back(i);
  return result;
}

}  // namespace pgba
