#include "averaging/connectivity.h"

#include <algorithm>
#include <map>
#include <numeric>
#include <utility>

namespace pgba {

UnionFind::UnionFind(int n) : parent_(n), size_(n, 1) { std::iota(parent_.begin(), parent_.end(), 0); }

int UnionFind::Find(int a) {
  while (parent_[a] != a) {
    parent_[a] = parent_[parent_[a]];
    a = parent_[a];
  }
  return a;
}

bool UnionFind::Union(int a, int b) {
  a = Find(a);
  b = Find(b);
  if (a == b) return false;
  if (size_[a] < size_[b] || (size_[a] == size_[b] && b < a)) std::swap(a, b);
  parent_[b] = a;
  size_[a] += size_[b];
  return true;
}

std::vector<int> MaximumSpanningForest(int num_nodes, const std::vector<WeightedEdge>& edges) {
  std::vector<int> order(edges.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return edges[a].weight > edges[b].weight; });
  UnionFind uf(num_nodes);
  std::vector<int> kept;
  for (int e : order)
    if (edges[e].i != edges[e].j && uf.Union(edges[e].i, edges[e].j)) kept.push_back(e);
  return kept;
}

std::set<uint32_t> LargestViewGraphComponent(const std::vector<TwoViewGeometry>& pairs) {
  std::map<uint32_t, int> index;  // ordered: node indices follow image ids
  for (const TwoViewGeometry& p : pairs) {
    index.emplace(p.image_id1, 0);
    index.emplace(p.image_id2, 0);
  }
  std::vector<uint32_t> ids;
  for (auto& [id, n] : index) {
    n = static_cast<int>(ids.size());
    ids.push_back(id);
  }
  UnionFind uf(static_cast<int>(ids.size()));
  for (const TwoViewGeometry& p : pairs) uf.Union(index[p.image_id1], index[p.image_id2]);
  int best = -1;
  for (int n = 0; n < static_cast<int>(ids.size()); ++n)  // first (smallest id) wins ties
    if (best < 0 || uf.SizeOf(n) > uf.SizeOf(best)) best = n;
  std::set<uint32_t> component;
  for (int n = 0; n < static_cast<int>(ids.size()); ++n)
    if (uf.Find(n) == uf.Find(best)) component.insert(ids[n]);
  return component;
}

std::vector<std::vector<int>> TripletComponents(const std::vector<LocalMotion>& triplets) {
  const int n = static_cast<int>(triplets.size());
  UnionFind uf(n);
  std::map<std::pair<uint32_t, uint32_t>, int> first_with_edge;
  for (int t = 0; t < n; ++t) {
    if (!HasDistinctImages(triplets[t])) continue;
    const auto& ids = triplets[t].image_ids;
    for (int a = 0; a < 3; ++a)
      for (int b = a + 1; b < 3; ++b) {
        const auto key = std::minmax(ids[a], ids[b]);
        auto [it, inserted] = first_with_edge.emplace(key, t);
        if (!inserted) uf.Union(it->second, t);
      }
  }
  // Members (ascending) and images per component root.
  std::map<int, std::vector<int>> members;
  std::map<int, std::set<uint32_t>> images;
  for (int t = 0; t < n; ++t) {
    if (!HasDistinctImages(triplets[t])) continue;
    const int r = uf.Find(t);
    members[r].push_back(t);
    images[r].insert(triplets[t].image_ids.begin(), triplets[t].image_ids.end());
  }
  std::vector<std::vector<int>> components;
  std::vector<size_t> num_images;
  for (auto& [r, m] : members) {
    components.push_back(std::move(m));
    num_images.push_back(images[r].size());
  }
  std::vector<int> order(components.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    if (num_images[a] != num_images[b]) return num_images[a] > num_images[b];
    if (components[a].size() != components[b].size()) return components[a].size() > components[b].size();
    return components[a].front() < components[b].front();
  });
  std::vector<std::vector<int>> sorted;
  sorted.reserve(order.size());
  for (int c : order) sorted.push_back(std::move(components[c]));
  return sorted;
}

std::vector<int> LargestTripletComponent(const std::vector<LocalMotion>& triplets) {
  std::vector<std::vector<int>> components = TripletComponents(triplets);
  return components.empty() ? std::vector<int>() : std::move(components.front());
}

std::set<uint32_t> ImagesOfTriplets(const std::vector<LocalMotion>& triplets, const std::vector<int>& indices) {
  std::set<uint32_t> images;
  for (int t : indices) images.insert(triplets[t].image_ids.begin(), triplets[t].image_ids.end());
  return images;
}

}  // namespace pgba
