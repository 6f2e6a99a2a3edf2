#include "mapper/dropped_images.h"

#include <algorithm>
#include <map>
#include <set>

namespace pgba {

std::vector<DroppedImage> DroppedImages(const Reconstruction& tracks, const PointlessMapperResult& result) {
  std::set<uint32_t> paired;
  for (const TwoViewGeometry& p : result.initial.pairs) paired.insert(p.image_id1), paired.insert(p.image_id2);
  // Initialised: in the largest model's initial poses or not left out by it, or in another
  // model's initial poses.
  const std::vector<uint32_t>& init_dropped = result.initial.init.dropped_image_ids;
  const auto initialised = [&](uint32_t id) {
    if (std::find(init_dropped.begin(), init_dropped.end(), id) == init_dropped.end()) return true;
    return std::any_of(result.more_models.begin(), result.more_models.end(),
                       [&](const ComponentModel& m) { return m.init.poses.count(id) > 0; });
  };
  std::map<uint32_t, const ImageVerdict*> failed;
  for (const ImageVerificationResult* v : result.Verifications())
    for (const ImageVerdict& d : v->verdicts)
      if (d.status == ImageVerdictStatus::kDropped) failed[d.image_id] = &d;
  std::vector<DroppedImage> out;
  for (const auto& [id, image] : tracks.images) {
    if (result.Placed(id)) continue;
    const bool observed = std::any_of(image.points2D.begin(), image.points2D.end(),
                                      [](const Point2D& p) { return p.point3D_id != kNoPoint3D; });
    const auto not_joined = result.joining.not_joined.find(id);
    const std::string why_not_joined =
        not_joined == result.joining.not_joined.end() ? std::string() : not_joined->second;
    std::string reason;
    if (!observed) {
      reason = "no feature matched to another image";
    } else if (!paired.count(id)) {
      reason = "no image pair verified (too few matches agreeing on one relative pose)";
    } else if (const auto v = failed.find(id); v != failed.end()) {
      reason = "its pose failed the final check against the points" +
               (v->second->reason.empty() ? "" : " (" + v->second->reason + ")");
    } else if (!initialised(id)) {
      reason = "not connected to the others by consistent image triplets" +
               (why_not_joined.empty() ? "" : "; " + why_not_joined);
    } else if (!why_not_joined.empty()) {
      reason = why_not_joined;
    } else {
      reason = "its triplets were unusable in the global bundle adjustment";
    }
    out.push_back({image.name, reason});
  }
  std::sort(out.begin(), out.end(), [](const DroppedImage& a, const DroppedImage& b) { return a.name < b.name; });
  return out;
}

std::string DroppedImagesSummary(const std::vector<DroppedImage>& dropped, size_t num_images) {
  if (dropped.empty()) return "";
  // Grouped by reason, in the order of the reasons' first images.
  std::vector<std::pair<std::string, std::vector<std::string>>> groups;
  for (const DroppedImage& d : dropped) {
    auto it = std::find_if(groups.begin(), groups.end(), [&](const auto& g) { return g.first == d.reason; });
    if (it == groups.end()) it = groups.insert(groups.end(), {d.reason, {}});
    it->second.push_back(d.name);
  }
  std::string line = std::to_string(dropped.size()) + " of " + std::to_string(num_images) +
                     (num_images == 1 ? " image" : " images") + " not registered";
  for (const auto& [reason, names] : groups) {
    line += "; " + reason + ": ";
    for (size_t i = 0; i < names.size(); ++i) line += (i ? ", " : "") + names[i];
  }
  return line + ". Photos that overlap more with the others (60% or more, from nearby viewpoints) can join";
}

nlohmann::json DroppedImagesJson(const std::vector<DroppedImage>& dropped) {
  nlohmann::json out = nlohmann::json::object();
  for (const DroppedImage& d : dropped) out[d.name] = d.reason;
  return out;
}

nlohmann::json ImageFates(const Reconstruction& tracks, const PointlessMapperResult& r,
                          const std::vector<DroppedImage>& dropped) {
  const std::vector<const Reconstruction*> models = r.Models();
  std::map<std::string, std::string> reasons;
  for (const DroppedImage& d : dropped) reasons[d.name] = d.reason;
  std::map<uint32_t, const ImageVerdict*> reregistered;
  for (const ImageVerificationResult* v : r.Verifications())
    for (const ImageVerdict& d : v->verdicts)
      if (d.status == ImageVerdictStatus::kReregistered) reregistered[d.image_id] = &d;
  nlohmann::json fates = nlohmann::json::array();
  for (const auto& [id, image] : tracks.images) {
    nlohmann::json f = {{"image", image.name}, {"model", nullptr}};
    for (size_t m = 0; m < models.size() && f["model"].is_null(); ++m)
      if (models[m]->images.count(id)) {
        f["model"] = m;
        f["registered_by"] = r.joining.joined.count(id) ? "absolute_pose" : "triplets";
        if (const auto v = reregistered.find(id); v != reregistered.end()) f["registered_again"] = v->second->reason;
      }
    if (f["model"].is_null()) {
      const auto reason = reasons.find(image.name);
      f["reason"] = reason != reasons.end() ? reason->second : "in no model";
    }
    fates.push_back(f);
  }
  return fates;
}

}  // namespace pgba
