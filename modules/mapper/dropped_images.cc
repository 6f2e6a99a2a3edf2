#include "mapper/dropped_images.h"

#include <algorithm>
#include <set>

namespace pgba {

std::vector<DroppedImage> DroppedImages(const Reconstruction& tracks, const PointlessMapperResult& result) {
  std::set<uint32_t> paired;
  for (const TwoViewGeometry& p : result.initial.pairs) paired.insert(p.image_id1), paired.insert(p.image_id2);
  const std::vector<uint32_t>& init_dropped = result.initial.init.dropped_image_ids;
  const std::vector<ImageVerdict>& verdicts = result.verification.verdicts;
  std::vector<DroppedImage> out;
  for (const auto& [id, image] : tracks.images) {
    if (result.refined.poses.count(id)) continue;
    const bool observed = std::any_of(image.points2D.begin(), image.points2D.end(),
                                      [](const Point2D& p) { return p.point3D_id != kNoPoint3D; });
    std::string reason;
    if (!observed) {
      reason = "no feature matched to another image";
    } else if (!paired.count(id)) {
      reason = "no image pair verified (too few matches agreeing on one relative pose)";
    } else if (std::find(init_dropped.begin(), init_dropped.end(), id) != init_dropped.end()) {
      reason = "not connected to the others by consistent image triplets";
    } else if (const auto v = std::find_if(verdicts.begin(), verdicts.end(),
                                           [&](const ImageVerdict& d) {
                                             return d.image_id == id && d.status == ImageVerdictStatus::kDropped;
                                           });
               v != verdicts.end()) {
      reason = "its pose failed the final check against the points" + (v->reason.empty() ? "" : " (" + v->reason + ")");
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

}  // namespace pgba
