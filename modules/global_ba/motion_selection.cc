#include "modules/global_ba/motion_selection.h"

#include <algorithm>
#include <numeric>
#include <set>
#include <string>

#include "pgba/util/error.h"

namespace pgba {

namespace {

int Find(std::vector<int>& parent, int i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

bool Usable(const LocalHessian& h) {
  const int dim = 6 * h.num_views() + h.num_intrinsics();
  return h.status == LocalHessianStatus::kOk && h.h.rows() == dim && h.h.allFinite() && h.h.MaxDiagonal() > 0;
}

}  // namespace

MotionSelection SelectMotions(const std::map<uint32_t, Pose>& initial_poses, const std::vector<LocalMotion>& motions,
                              const std::vector<LocalHessian>& hessians) {
  for (const auto& [id, pose] : initial_poses)
    if (!pose.q().coeffs().allFinite() || !pose.t().allFinite())
      throw InputError("global BA: initial pose of image " + std::to_string(id) + " is not finite");
  std::vector<bool> seen(motions.size(), false);
  for (size_t i = 0; i < hessians.size(); ++i) {
    const LocalHessian& h = hessians[i];
    if (h.motion_index < 0 || h.motion_index >= static_cast<int>(motions.size()) ||
        h.image_ids != motions[h.motion_index].image_ids || seen[h.motion_index])
      throw InputError("global BA: local hessian " + std::to_string(i) + " does not match the motion list (motion " +
                       std::to_string(h.motion_index) + ")");
    seen[h.motion_index] = true;
  }

  // Candidates, then union-find over motions sharing an image pair.
  std::vector<int> candidates;
  for (size_t i = 0; i < hessians.size(); ++i) {
    const LocalHessian& h = hessians[i];
    bool ok = Usable(h);
    for (uint32_t id : h.image_ids) ok = ok && initial_poses.count(id) > 0;
    if (ok) candidates.push_back(static_cast<int>(i));
  }
  std::vector<int> parent(candidates.size());
  std::iota(parent.begin(), parent.end(), 0);
  std::map<std::pair<uint32_t, uint32_t>, int> pair_owner;
  for (size_t c = 0; c < candidates.size(); ++c) {
    const auto& ids = hessians[candidates[c]].image_ids;
    for (size_t a = 0; a < ids.size(); ++a)
      for (size_t b = a + 1; b < ids.size(); ++b) {
        const auto key = std::minmax(ids[a], ids[b]);
        const auto [it, inserted] = pair_owner.emplace(key, static_cast<int>(c));
        if (!inserted) parent[Find(parent, static_cast<int>(c))] = Find(parent, it->second);
      }
  }
  std::map<int, std::set<uint32_t>> component_images;
  for (size_t c = 0; c < candidates.size(); ++c)
    for (uint32_t id : hessians[candidates[c]].image_ids)
      component_images[Find(parent, static_cast<int>(c))].insert(id);
  int best = -1;
  size_t best_size = 0;
  for (const auto& [root, images] : component_images)  // ascending root: ties keep the first
    if (images.size() > best_size) {
      best = root;
      best_size = images.size();
    }

  MotionSelection sel;
  for (size_t c = 0; c < candidates.size(); ++c)
    if (Find(parent, static_cast<int>(c)) == best) sel.hessian_indices.push_back(candidates[c]);
  sel.num_excluded = static_cast<int>(hessians.size() - sel.hessian_indices.size());
  if (best >= 0) sel.images.assign(component_images[best].begin(), component_images[best].end());
  for (const auto& [id, pose] : initial_poses)
    if (!std::binary_search(sel.images.begin(), sel.images.end(), id)) sel.excluded_images.push_back(id);
  return sel;
}

}  // namespace pgba
