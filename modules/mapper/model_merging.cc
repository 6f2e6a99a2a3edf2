#include "mapper/model_merging.h"

#include <algorithm>
#include <limits>
#include <random>

namespace pgba {
namespace {

// The largest reprojection error of `X` (in `model`'s frame) over the views of `point`.
double MaxReprojectionError(const Reconstruction& model, const Point3D& point, const Eigen::Vector3d& X) {
  double worst = 0.0;
  for (const TrackElement& e : point.track) {
    const Image& image = model.images.at(e.image_id);
    const Eigen::Vector3d x_cam = image.pose.ToCamera(X);
    if (!(x_cam.z() > 0)) return std::numeric_limits<double>::infinity();
    const Eigen::Vector2d pixel = model.CameraOf(image).Project(x_cam);
    worst = std::max(worst, (pixel - image.points2D.at(e.point2D_idx).xy).norm());
  }
  return worst;
}

}  // namespace

std::string ModelAlignment::Summary() const {
  if (by == MergeEvidence::kVerifiedPairs)
    return "by " + std::to_string(agreeing_pairs) + (agreeing_pairs == 1 ? " verified pair" : " verified pairs");
  return "by " + std::to_string(inliers) + (inliers == 1 ? " shared point" : " shared points");
}

nlohmann::json ModelAlignment::ToJson() const {
  nlohmann::json j = {{"success", success}, {"shared_points", shared_points}, {"inliers", inliers},
                      {"shared_images", shared_images}};
  j["by"] = by == MergeEvidence::kVerifiedPairs ? "verified_pairs" : "shared_points";
  if (by == MergeEvidence::kVerifiedPairs) {
    j["pairs"] = pairs;
    j["agreeing_pairs"] = agreeing_pairs;
    j["conditioning"] = conditioning;
  }
  if (success) {
    j["scale"] = b_to_a.s;
    j["summary"] = Summary();
  }
  if (!reason.empty()) j["reason"] = reason;
  return j;
}

ModelAlignment AlignModels(const Reconstruction& a, const Reconstruction& b, const ModelAlignmentOptions& options) {
  ModelAlignment result;
  for (const auto& [id, image] : b.images)
    if (a.images.count(id)) result.shared_images.push_back(image.name);
  std::vector<const Point3D*> in_a, in_b;
  for (const auto& [id, point] : b.points3D) {
    const auto it = a.points3D.find(id);
    if (it == a.points3D.end()) continue;
    in_a.push_back(&it->second);
    in_b.push_back(&point);
  }
  const int n = static_cast<int>(in_a.size());
  result.shared_points = n;
  if (n < std::max(3, options.min_shared_points)) {
    result.reason = std::to_string(n) + " shared points (fewer than " + std::to_string(options.min_shared_points) + ")";
    return result;
  }
  auto inliers_of = [&](const Sim3& sim, std::vector<int>* inliers) {
    const Sim3 inverse = sim.Inverse();
    inliers->clear();
    for (int i = 0; i < n; ++i)
      if (MaxReprojectionError(a, *in_a[i], sim.Apply(in_b[i]->xyz)) <= options.max_reprojection_px &&
          MaxReprojectionError(b, *in_b[i], inverse.Apply(in_a[i]->xyz)) <= options.max_reprojection_px)
        inliers->push_back(i);
  };
  std::mt19937_64 rng(options.seed);
  std::uniform_int_distribution<int> pick(0, n - 1);
  std::vector<int> best, inliers;
  Sim3 best_sim;
  for (int it = 0; it < options.ransac_iterations; ++it) {
    const int i = pick(rng), j = pick(rng), k = pick(rng);
    if (i == j || j == k || i == k) continue;
    Sim3 sim;
    if (!EstimateSim3({in_b[i]->xyz, in_b[j]->xyz, in_b[k]->xyz}, {in_a[i]->xyz, in_a[j]->xyz, in_a[k]->xyz}, &sim))
      continue;
    inliers_of(sim, &inliers);
    if (inliers.size() > best.size()) {
      best.swap(inliers);
      best_sim = sim;
    }
  }
  // Refit on the inliers, kept when it does not lose any.
  if (best.size() >= 3) {
    std::vector<Eigen::Vector3d> src, dst;
    for (int i : best) {
      src.push_back(in_b[i]->xyz);
      dst.push_back(in_a[i]->xyz);
    }
    Sim3 refit;
    if (EstimateSim3(src, dst, &refit)) {
      inliers_of(refit, &inliers);
      if (inliers.size() >= best.size()) {
        best.swap(inliers);
        best_sim = refit;
      }
    }
  }
  result.inliers = static_cast<int>(best.size());
  result.b_to_a = best_sim;
  if (result.inliers < options.min_inliers || result.inliers < options.min_inlier_ratio * n) {
    result.reason = std::to_string(result.inliers) + " of " + std::to_string(n) +
                    " shared points agree with one similarity";
    return result;
  }
  result.success = true;
  return result;
}

}  // namespace pgba
