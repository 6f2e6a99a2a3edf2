#include "modules/global_ba/relinearized_models.h"

#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include "pgba/util/logging.h"

namespace pgba::internal {

std::vector<int> Models::RetakeAt(const Reconstruction& tracks, const LocalHessianOptions& at_solution,
                                  const ObservationShares* shares, const std::vector<LocalMotion>& motions,
                                  const GlobalBAResult& result, const Models* start) {
  if (!start) start = this;
  const size_t n = motions.size();
  // Self-calibration: the models re-taken with the solution's intrinsics, the same unknowns.
  std::optional<Reconstruction> calibrated;
  FreeIntrinsics free;
  if (!result.intrinsics.empty()) {
    calibrated = tracks;
    for (const auto& [id, k] : result.intrinsics) {
      ScatterIntrinsics(k.values, k.free, &calibrated->cameras.at(id));
      free[id] = k.free;
    }
  }
  const Reconstruction& at = calibrated ? *calibrated : tracks;
  // Storage of their own, the first time: filled slot by slot below, the slots not re-taken
  // copied from the borrowed models after.
  const bool borrowed = hessians_ != &owned_hessians_;
  const bool borrowed_frames = frames_ != &owned_frames_;
  if (borrowed) owned_hessians_.assign(n, LocalHessian());
  if (borrowed_frames) owned_frames_.assign(n, LocalMotion());
  std::vector<char> replaced(n, 0);
  std::array<int, kNumLocalHessianStatus> counts{};
  std::vector<LocalHessianStatus> status(n, LocalHessianStatus::kOk);
  std::vector<char> tried(n, 0);
  std::unique_ptr<tbb::global_control> limit;
  if (at_solution.num_threads > 0)
    limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, at_solution.num_threads);
  // Each motion writes only its own slot: the result does not depend on scheduling.
  tbb::parallel_for(size_t(0), n, [&](size_t i) {
    if (!(result.irls_weights[i] > 0)) return;  // not used
    tried[i] = 1;
    LocalMotion t = motions[i];
    t.global_to_local = result.similarities[i];
    for (int v = 0; v < t.num_views(); ++v) t.local_poses[v] = t.global_to_local.Apply(result.poses.at(t.image_ids[v]));
    t.track_points = start->hessians()[i].track_points;
    if (t.track_points.size() == t.track_ids.size()) {
      const Sim3 old_to_new = t.global_to_local * start->frames()[i].global_to_local.Inverse();
      for (PointStart& p : t.track_points) p.X = old_to_new.Apply(p.X);
    } else {
      t.track_points.clear();
    }
    LocalHessian h = ComputeLocalHessian(at, t, static_cast<int>(i), at_solution, shares, free.empty() ? nullptr : &free);
    status[i] = h.status;
    if (h.status != LocalHessianStatus::kOk) return;  // keeps its previous model
    owned_hessians_[i] = std::move(h);
    owned_frames_[i] = std::move(t);
    replaced[i] = 1;
  });
  std::vector<int> index;
  size_t num_tried = 0;
  for (size_t i = 0; i < n; ++i) {
    num_tried += tried[i];
    if (tried[i]) ++counts[static_cast<int>(status[i])];
    if (replaced[i]) {
      index.push_back(static_cast<int>(i));
      continue;
    }
    if (borrowed) owned_hessians_[i] = (*hessians_)[i];
    if (borrowed_frames) owned_frames_[i] = (*frames_)[i];
  }
  frames_ = &owned_frames_;
  hessians_ = &owned_hessians_;
  std::string rejected;
  for (int s = 1; s < kNumLocalHessianStatus; ++s)
    if (counts[s] > 0)
      rejected += std::string(" ") + LocalHessianStatusName(static_cast<LocalHessianStatus>(s)) + "=" +
                  std::to_string(counts[s]);
  PGBA_LOG_DEBUG << "local hessians: " << counts[0] << " of " << num_tried << " motions ok"
                << (rejected.empty() ? "" : "; rejected:" + rejected);
  return index;
}

double TotalRobustCost(const std::vector<LocalHessian>& models, const GlobalBAResult& used) {
  double c = 0.0;
  for (size_t i = 0; i < models.size(); ++i)
    if (used.irls_weights[i] > 0) c += models[i].robust_cost;
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
