#include "pgba/scene/reconstruction.h"

#include <algorithm>
#include <set>
#include <stdexcept>
#include <utility>

namespace pgba {

std::optional<uint32_t> Reconstruction::FindImageByName(const std::string& name) const {
  for (const auto& [id, image] : images)
    if (image.name == name) return id;
  return std::nullopt;
}

size_t Reconstruction::NumObservations() const {
  size_t n = 0;
  for (const auto& [id, p] : points3D) n += p.track.size();
  return n;
}

uint64_t Reconstruction::AddPoint3D(const Eigen::Vector3d& xyz, std::vector<TrackElement> track) {
  // Check every element before linking any, so that a bad track leaves the scene untouched.
  std::set<std::pair<uint32_t, uint32_t>> seen;
  for (const auto& el : track) {
    const Point2D& obs = images.at(el.image_id).points2D.at(el.point2D_idx);
    if (obs.point3D_id != kNoPoint3D)
      throw std::invalid_argument("AddPoint3D: observation " + std::to_string(el.point2D_idx) + " of image " +
                                  std::to_string(el.image_id) + " already belongs to point " +
                                  std::to_string(obs.point3D_id));
    if (!seen.insert({el.image_id, el.point2D_idx}).second)
      throw std::invalid_argument("AddPoint3D: track lists observation " + std::to_string(el.point2D_idx) +
                                  " of image " + std::to_string(el.image_id) + " twice");
  }
  const uint64_t id = points3D.empty() ? 1 : points3D.rbegin()->first + 1;
  for (const auto& el : track) images.at(el.image_id).points2D[el.point2D_idx].point3D_id = static_cast<int64_t>(id);
  Point3D& p = points3D[id];
  p.point3D_id = id;
  p.xyz = xyz;
  p.track = std::move(track);
  return id;
}

void Reconstruction::DeletePoint3D(uint64_t point3D_id) {
  auto it = points3D.find(point3D_id);
  if (it == points3D.end()) return;
  for (const auto& el : it->second.track) {
    auto im = images.find(el.image_id);
    if (im != images.end() && el.point2D_idx < im->second.points2D.size())
      im->second.points2D[el.point2D_idx].point3D_id = kNoPoint3D;
  }
  points3D.erase(it);
}

void Reconstruction::KeepImages(const std::vector<uint32_t>& image_ids) {
  const std::set<uint32_t> keep(image_ids.begin(), image_ids.end());
  for (auto it = images.begin(); it != images.end();)
    it = keep.count(it->first) ? std::next(it) : images.erase(it);
  std::vector<uint64_t> dead;
  for (auto& [id, p] : points3D) {
    auto& tr = p.track;
    tr.erase(std::remove_if(tr.begin(), tr.end(), [&](const TrackElement& e) { return !keep.count(e.image_id); }),
             tr.end());
    if (tr.size() < 2) dead.push_back(id);
  }
  for (uint64_t id : dead) DeletePoint3D(id);
}

std::string Reconstruction::CheckConsistency() const {
  for (const auto& [id, camera] : cameras)
    if (camera.camera_id != id)
      return "camera key " + std::to_string(id) + " holds camera_id " + std::to_string(camera.camera_id);
  for (const auto& [id, image] : images) {
    if (image.image_id != id)
      return "image key " + std::to_string(id) + " holds image_id " + std::to_string(image.image_id);
    if (!cameras.count(image.camera_id))
      return "image " + std::to_string(id) + " refers to missing camera " + std::to_string(image.camera_id);
    for (size_t k = 0; k < image.points2D.size(); ++k) {
      const int64_t pid = image.points2D[k].point3D_id;
      if (pid == kNoPoint3D) continue;
      auto p = points3D.find(static_cast<uint64_t>(pid));
      if (p == points3D.end())
        return "image " + std::to_string(id) + " observation " + std::to_string(k) + " refers to missing point " +
               std::to_string(pid);
      const auto& tr = p->second.track;
      // A copy: a lambda may not capture a structured binding in C++17 (clang rejects it).
      const uint32_t image_id = id;
      if (std::none_of(tr.begin(), tr.end(), [&](const TrackElement& e) {
            return e.image_id == image_id && e.point2D_idx == k;
          }))
        return "point " + std::to_string(pid) + " does not list image " + std::to_string(id) + " observation " +
               std::to_string(k);
    }
  }
  for (const auto& [pid, p] : points3D) {
    if (p.point3D_id != pid)
      return "point key " + std::to_string(pid) + " holds point3D_id " + std::to_string(p.point3D_id);
    std::vector<std::pair<uint32_t, uint32_t>> elements;
    for (const auto& e : p.track) elements.emplace_back(e.image_id, e.point2D_idx);
    std::sort(elements.begin(), elements.end());
    const auto dup = std::adjacent_find(elements.begin(), elements.end());
    if (dup != elements.end())
      return "point " + std::to_string(pid) + " lists image " + std::to_string(dup->first) + " observation " +
             std::to_string(dup->second) + " twice";
    for (const auto& e : p.track) {
      auto im = images.find(e.image_id);
      if (im == images.end())
        return "point " + std::to_string(pid) + " refers to missing image " + std::to_string(e.image_id);
      if (e.point2D_idx >= im->second.points2D.size())
        return "point " + std::to_string(pid) + " refers to observation " + std::to_string(e.point2D_idx) +
               " beyond the " + std::to_string(im->second.points2D.size()) + " of image " +
               std::to_string(e.image_id);
      if (im->second.points2D[e.point2D_idx].point3D_id != static_cast<int64_t>(pid))
        return "image " + std::to_string(e.image_id) + " observation " + std::to_string(e.point2D_idx) +
               " does not point back to point " + std::to_string(pid);
    }
  }
  return "";
}

}  // namespace pgba
