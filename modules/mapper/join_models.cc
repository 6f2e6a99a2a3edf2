#include "mapper/join_models.h"

#include <algorithm>
#include <set>
#include <utility>

#include "pgba/util/logging.h"

namespace pgba {
namespace {

// The image sets of the models, in order (to tell whether joining changed any).
std::vector<std::set<uint32_t>> ImageSets(const std::vector<GlobalInitResult>& models) {
  std::vector<std::set<uint32_t>> sets;
  for (const GlobalInitResult& m : models) {
    sets.emplace_back();
    for (const auto& [id, pose] : m.poses) sets.back().insert(id);
  }
  return sets;
}

}  // namespace

GlobalInitResult AdjustedStart(const GlobalInitResult& init, const std::map<uint32_t, Pose>& poses) {
  GlobalInitResult start = init;
  start.poses = poses;
  std::vector<LocalMotion> triplets;
  for (const LocalMotion& t : init.triplets)
    if (std::all_of(t.image_ids.begin(), t.image_ids.end(), [&](uint32_t id) { return poses.count(id); }))
      triplets.push_back(t);
  start.triplets = std::move(triplets);
  return start;
}

std::vector<GlobalInitResult> JoinModels(const Reconstruction& tracks, const std::vector<TwoViewGeometry>& pairs,
                                         const ComponentJoiningOptions& options, const PointlessMapperResult& r,
                                         Report* report, ComponentJoiningResult* joining) {
  StageTimer timer(report, "components");
  std::vector<GlobalInitResult> models = {AdjustedStart(r.initial.init, r.refined.poses)};
  for (const ComponentModel& m : r.more_models) models.push_back(AdjustedStart(m.init, m.refined.poses));
  const std::vector<std::set<uint32_t>> before = ImageSets(models);
  *joining = JoinComponents(tracks, pairs, options, &models);
  nlohmann::json& stage = timer.Stop();
  stage.update(joining->ToJson(tracks));
  stage["models"] = nlohmann::json::array();
  for (const GlobalInitResult& m : models) stage["models"].push_back(m.poses.size());
  for (const auto& [id, reason] : joining->not_joined)
    PGBA_LOG_DEBUG << "image " << tracks.images.at(id).name << " in no model: " << reason;  // listed at the end
  const bool changed = models.size() > 1 || !joining->joined.empty() || !joining->merges.empty();
  internal::LogLine(changed ? LogLevel::kInfo : LogLevel::kDebug)
      << "models: " << models.size() << " after joining (" << joining->joined.size()
      << " images added by absolute pose against a model's points, " << joining->merges.size()
      << " merges of models sharing points or verified pairs)";
  if (ImageSets(models) == before) return {};
  return models;
}

}  // namespace pgba
