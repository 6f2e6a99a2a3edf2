#include "modules/global_ba/relinearized_models.h"

#include <utility>

namespace pgba::internal {

void Models::Adopt(Retaken&& r) {
  std::vector<int> slot(hessians_->size(), -1);
  for (size_t j = 0; j < r.index.size(); ++j) slot[r.index[j]] = static_cast<int>(j);
  std::vector<LocalMotion> frames;
  std::vector<LocalHessian> hessians;
  frames.reserve(slot.size());
  hessians.reserve(slot.size());
  for (size_t i = 0; i < slot.size(); ++i) {
    if (slot[i] < 0) {
      frames.push_back((*frames_)[i]);
      hessians.push_back((*hessians_)[i]);
    } else {
      frames.push_back(std::move(r.frames[slot[i]]));
      hessians.push_back(std::move(r.hessians[slot[i]]));
    }
  }
  owned_frames_ = std::move(frames);
  owned_hessians_ = std::move(hessians);
  frames_ = &owned_frames_;
  hessians_ = &owned_hessians_;
}

Models::Retaken RelinearizeAt(const Reconstruction& tracks, const LocalHessianOptions& at_solution,
                              const ObservationShares* shares, const std::vector<LocalMotion>& motions,
                              const Models& models, const GlobalBAResult& result) {
  std::vector<LocalMotion> predicted;
  std::vector<int> index;
  for (size_t i = 0; i < motions.size(); ++i) {
    if (!(result.irls_weights[i] > 0)) continue;  // not used
    LocalMotion t = motions[i];
    t.global_to_local = result.similarities[i];
    for (int v = 0; v < t.num_views(); ++v) t.local_poses[v] = t.global_to_local.Apply(result.poses.at(t.image_ids[v]));
    t.track_points = models.hessians()[i].track_points;
    if (t.track_points.size() == t.track_ids.size()) {
      const Sim3 old_to_new = t.global_to_local * models.frames()[i].global_to_local.Inverse();
      for (PointStart& p : t.track_points) p.X = old_to_new.Apply(p.X);
    } else {
      t.track_points.clear();
    }
    predicted.push_back(std::move(t));
    index.push_back(static_cast<int>(i));
  }
  LocalHessianResult lr;
  if (result.intrinsics.empty()) {
    lr = ComputeLocalHessians(tracks, predicted, at_solution, shares);
  } else {
    // Self-calibration: the models re-taken with the solution's intrinsics, the same unknowns.
    Reconstruction at = tracks;
    FreeIntrinsics free;
    for (const auto& [id, k] : result.intrinsics) {
      ScatterIntrinsics(k.values, k.free, &at.cameras.at(id));
      free[id] = k.free;
    }
    lr = ComputeLocalHessians(at, predicted, at_solution, shares, &free);
  }
  Models::Retaken r;
  for (size_t j = 0; j < index.size(); ++j) {
    if (lr.hessians[j].status != LocalHessianStatus::kOk) continue;  // keeps its previous model
    r.index.push_back(index[j]);
    r.frames.push_back(std::move(predicted[j]));
    r.hessians.push_back(std::move(lr.hessians[j]));
    r.hessians.back().motion_index = index[j];
  }
  return r;
}

double TotalRobustCost(const std::vector<LocalHessian>& models, const Models::Retaken* retaken,
                       const GlobalBAResult& used) {
  std::vector<const LocalHessian*> model(models.size());
  for (size_t i = 0; i < models.size(); ++i) model[i] = &models[i];
  if (retaken)
    for (size_t j = 0; j < retaken->index.size(); ++j) model[retaken->index[j]] = &retaken->hessians[j];
  double c = 0.0;
  for (size_t i = 0; i < models.size(); ++i)
    if (used.irls_weights[i] > 0) c += model[i]->robust_cost;
  return c;
}

ObservationShares SharesOf(const Reconstruction& tracks, const std::vector<LocalMotion>& motions,
                           const LocalHessianOptions& at_solution) {
  return at_solution.shared_observation_weighting ? CountObservationShares(tracks, motions) : ObservationShares();
}

FreeIntrinsics FreeIntrinsicsOf(const std::vector<LocalHessian>& hessians) {
  FreeIntrinsics free;
  for (const LocalHessian& h : hessians)
    for (size_t c = 0; c < h.intrinsic_camera_ids.size(); ++c) free[h.intrinsic_camera_ids[c]] = h.intrinsic_free[c];
  return free;
}

}  // namespace pgba::internal
