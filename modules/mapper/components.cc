#include "mapper/components.h"

#include <algorithm>
#include <set>

#include "mapper/pair_alignment.h"
#include "pgba/io/option_ranges.h"
#include "pgba/scene/triangulate_model.h"
#include "pgba/util/logging.h"

namespace pgba {
namespace {

constexpr const char* kJoiningOff = "in no triplet, and joining by absolute pose is off (components.join_images)";

std::vector<std::string> NamesOf(const Reconstruction& tracks, const std::map<uint32_t, Pose>& poses) {
  std::vector<std::string> names;
  for (const auto& [id, pose] : poses) names.push_back(tracks.images.at(id).name);
  return names;
}

// Model `b` mapped into the frame of `a` (X_a = b_to_a(X_b)) and added to it: the images a
// lacks, every triplet of b with its similarity composed (its local frame is unchanged).
void MergeInto(const GlobalInitResult& b, const Sim3& b_to_a, GlobalInitResult* a) {
  for (const auto& [id, pose] : b.poses)
    if (!a->poses.count(id)) a->poses[id] = b_to_a.Apply(pose);
  const Sim3 a_to_b = b_to_a.Inverse();
  for (LocalMotion t : b.triplets) {
    t.global_to_local = t.global_to_local * a_to_b;
    a->triplets.push_back(std::move(t));
  }
}

// Removes `image_id` from `model` with the triplets that hold it.
void RemoveImage(uint32_t image_id, GlobalInitResult* model) {
  model->poses.erase(image_id);
  std::vector<LocalMotion> kept;
  for (LocalMotion& t : model->triplets)
    if (std::find(t.image_ids.begin(), t.image_ids.end(), image_id) == t.image_ids.end()) kept.push_back(std::move(t));
  model->triplets = std::move(kept);
}

void SetDropped(const Reconstruction& tracks, GlobalInitResult* model) {
  model->dropped_image_ids.clear();
  model->images_dropped.clear();
  for (const auto& [id, image] : tracks.images) {
    if (model->poses.count(id)) continue;
    model->dropped_image_ids.push_back(id);
    model->images_dropped.push_back(image.name);
  }
  model->stats.images_registered = static_cast<int>(model->poses.size());
  model->stats.triplets_kept = static_cast<int>(model->triplets.size());
}

}  // namespace

std::string ComponentJoiningOptions::Check() const {
  if (const std::string p = CheckRanges(*this, "components"); !p.empty()) return p;
  if (!(registration.absolute_pose.min_inliers <= registration.min_correspondences))
    return "min_pose_inliers = " + std::to_string(registration.absolute_pose.min_inliers) +
           " exceeds min_correspondences = " + std::to_string(registration.min_correspondences);
  return "";
}

nlohmann::json ComponentJoiningResult::ToJson(const Reconstruction& tracks) const {
  nlohmann::json j;
  j["rounds"] = rounds;
  j["joined"] = nlohmann::json::array();
  for (const auto& [id, r] : joined) {
    nlohmann::json e = r.ToJson();
    e["image"] = tracks.images.at(id).name;
    j["joined"].push_back(e);
  }
  j["not_joined"] = nlohmann::json::array();
  for (const auto& [id, reason] : not_joined)
    j["not_joined"].push_back({{"image", tracks.images.at(id).name}, {"reason", reason}});
  j["merges"] = nlohmann::json::array();
  for (const ModelMergeRecord& m : merges) {
    nlohmann::json e = m.alignment.ToJson();
    e["into"] = m.into;
    e["from"] = m.from;
    j["merges"].push_back(e);
  }
  return j;
}

ComponentJoiningResult JoinComponents(const Reconstruction& tracks, const std::vector<TwoViewGeometry>& pairs,
                                      const ComponentJoiningOptions& options, std::vector<GlobalInitResult>* models) {
  ComponentJoiningResult result;
  std::set<uint32_t> with_pair;
  for (const TwoViewGeometry& p : pairs) {
    with_pair.insert(p.image_id1);
    with_pair.insert(p.image_id2);
  }
  auto in_a_model = [&](uint32_t id) {
    return std::any_of(models->begin(), models->end(), [&](const GlobalInitResult& m) { return m.poses.count(id); });
  };
  for (int round = 0; round < options.max_rounds && !models->empty(); ++round) {
    // Nothing to join nor merge: no triangulation.
    const bool any_candidate = std::any_of(tracks.images.begin(), tracks.images.end(), [&](const auto& entry) {
      return with_pair.count(entry.first) && !in_a_model(entry.first);
    });
    if ((!any_candidate || !options.join_images) && (models->size() == 1 || !options.merge_models)) {
      for (const auto& [id, image] : tracks.images)
        if (!in_a_model(id))
          result.not_joined[id] = with_pair.count(id) ? kJoiningOff : "no verified pair";
      break;
    }
    std::vector<Reconstruction> structures;
    for (const GlobalInitResult& m : *models) structures.push_back(TriangulateModel(tracks, m.poses));
    // Every image in no model, against every model.
    bool changed = false;
    result.not_joined.clear();
    std::map<uint32_t, std::vector<std::pair<int, AbsoluteRegistration>>> accepted;
    for (const auto& [id, image] : tracks.images) {
      if (in_a_model(id)) continue;
      if (!with_pair.count(id)) {
        result.not_joined[id] = "no verified pair";
        continue;
      }
      if (!options.join_images) {
        result.not_joined[id] = kJoiningOff;
        continue;
      }
      std::string reason;
      int best_inliers = -1;
      for (size_t m = 0; m < models->size(); ++m) {
        const AbsoluteRegistration r = RegisterByAbsolutePose(tracks, structures[m], pairs, id, options.registration);
        const std::string problem =
            CheckRegistration(tracks, pairs, (*models)[m].poses, r, options.registration);
        if (problem.empty()) {
          accepted[id].push_back({static_cast<int>(m), r});
        } else if (r.inliers > best_inliers) {
          best_inliers = r.inliers;
          reason = "absolute pose against " +
                   (models->size() > 1 ? "model " + std::to_string(m) + "'s" : std::string("the")) +
                   " points: " + problem;
        }
      }
      if (!accepted.count(id)) result.not_joined[id] = reason;
    }
    for (const auto& [id, registrations] : accepted) {
      for (const auto& [m, r] : registrations) {
        (*models)[m].poses[id] = r.pose;
        PGBA_LOG_INFO << "image " << tracks.images.at(id).name << " joins model " << m << " by absolute pose: "
                      << r.inliers << " inliers of " << r.correspondences << ", " << r.pairs
                      << " verified pairs agreeing within " << r.pair_rotation_median_deg << " deg (median)";
      }
      result.joined[id] = registrations.front().second;
      changed = true;
    }
    // Models that share points are merged, the smaller into the larger.
    bool merged = false;
    if (options.merge_models && models->size() > 1) {
      if (changed) {
        structures.clear();
        for (const GlobalInitResult& m : *models) structures.push_back(TriangulateModel(tracks, m.poses));
      }
      for (size_t a = 0; a < models->size() && !merged; ++a)
        for (size_t b = a + 1; b < models->size() && !merged; ++b) {
          ModelAlignment alignment = AlignModels(structures[a], structures[b], options.alignment);
          if (!alignment.success && alignment.shared_points < options.alignment.min_shared_points) {
            // Too few shared points to judge a similarity: the verified pairs between them.
            ModelAlignment by_pairs = AlignModelsByPairs(tracks, pairs, (*models)[a].poses, (*models)[b].poses,
                                                         options.pairs, options.registration.verification);
            if (by_pairs.success || by_pairs.pairs > 0) {
              by_pairs.shared_points = alignment.shared_points;
              by_pairs.shared_images = alignment.shared_images;
              alignment = std::move(by_pairs);
            }
          }
          if (!alignment.success) {
            if (!alignment.shared_images.empty() || alignment.pairs > 0)
              PGBA_LOG_INFO << "models " << a << " and " << b << " are not merged: " << alignment.reason;
            continue;
          }
          ModelMergeRecord record{NamesOf(tracks, (*models)[a].poses), NamesOf(tracks, (*models)[b].poses),
                                  alignment};
          PGBA_LOG_INFO << "model " << b << " (" << record.from.size() << " images) merged into model " << a << " ("
                        << record.into.size() << " images) " << alignment.Summary()
                        << (alignment.by == MergeEvidence::kVerifiedPairs
                                ? " of " + std::to_string(alignment.pairs) + " between them"
                                : " of " + std::to_string(alignment.shared_points) + ", " +
                                      std::to_string(alignment.shared_images.size()) + " shared images");
          MergeInto((*models)[b], alignment.b_to_a, &(*models)[a]);
          models->erase(models->begin() + static_cast<long>(b));
          result.merges.push_back(std::move(record));
          merged = true;
        }
    }
    result.rounds = round + 1;
    if (!changed && !merged) break;
  }
  // An image still in two models stays in the larger.
  std::stable_sort(models->begin(), models->end(),
                   [](const GlobalInitResult& a, const GlobalInitResult& b) { return a.poses.size() > b.poses.size(); });
  std::set<uint32_t> placed;
  for (GlobalInitResult& m : *models) {
    std::vector<uint32_t> duplicates;
    for (const auto& [id, pose] : m.poses)
      if (placed.count(id)) duplicates.push_back(id);
    for (uint32_t id : duplicates) RemoveImage(id, &m);
    for (const auto& [id, pose] : m.poses) placed.insert(id);
  }
  models->erase(std::remove_if(models->begin(), models->end(),
                               [](const GlobalInitResult& m) { return m.poses.size() < 3; }),
                models->end());
  for (GlobalInitResult& m : *models) SetDropped(tracks, &m);
  for (auto it = result.joined.begin(); it != result.joined.end();)
    it = in_a_model(it->first) ? std::next(it) : result.joined.erase(it);
  return result;
}

}  // namespace pgba
