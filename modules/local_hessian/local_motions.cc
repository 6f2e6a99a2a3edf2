#include "modules/local_hessian/local_motions.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <set>

#include "pgba/io/option_ranges.h"
#include "modules/local_hessian/local_bundle.h"
#include "pgba/util/logging.h"

namespace pgba {

namespace {

// Tracks shared by every pair of registered images (each track counted once per pair).
std::map<uint32_t, std::map<uint32_t, int>> SharedTracks(const Reconstruction& tracks,
                                                         const std::map<uint32_t, Pose>& poses) {
  std::map<uint32_t, std::map<uint32_t, int>> shared;
  for (const auto& [track_id, point] : tracks.points3D) {
    std::set<uint32_t> images;
    for (const TrackElement& el : point.track)
      if (poses.count(el.image_id)) images.insert(el.image_id);
    for (auto a = images.begin(); a != images.end(); ++a)
      for (auto b = std::next(a); b != images.end(); ++b) {
        ++shared[*a][*b];
        ++shared[*b][*a];
      }
  }
  return shared;
}

// Tracks of each registered image (each once, ascending).
std::map<uint32_t, std::vector<uint64_t>> TracksPerImage(const Reconstruction& tracks,
                                                        const std::map<uint32_t, Pose>& poses) {
  std::map<uint32_t, std::vector<uint64_t>> out;
  for (const auto& [track_id, point] : tracks.points3D)
    for (const TrackElement& el : point.track)
      if (poses.count(el.image_id)) {
        std::vector<uint64_t>& v = out[el.image_id];
        if (v.empty() || v.back() != track_id) v.push_back(track_id);
      }
  return out;
}

// Tracks seen by at least two of `image_ids`, ascending.
std::vector<uint64_t> TracksOfViews(const std::map<uint32_t, std::vector<uint64_t>>& per_image,
                                    const std::vector<uint32_t>& image_ids) {
  std::map<uint64_t, int> views_of_track;
  for (const uint32_t id : image_ids)
    if (const auto it = per_image.find(id); it != per_image.end())
      for (const uint64_t t : it->second) ++views_of_track[t];
  std::vector<uint64_t> out;
  for (const auto& [t, n] : views_of_track)
    if (n >= 2) out.push_back(t);
  return out;
}

}  // namespace

std::vector<LocalMotion> SelectLocalMotions(const Reconstruction& tracks, const std::map<uint32_t, Pose>& poses,
                                            const LocalMotionOptions& options) {
  std::vector<LocalMotion> motions;
  if (options.views <= 3) return motions;
  const auto shared = SharedTracks(tracks, poses);
  const auto per_image = TracksPerImage(tracks, poses);
  std::set<std::vector<uint32_t>> seen;  // image sets already modelled
  for (const int stride : options.neighbour_strides) {
    if (stride < 1) continue;
    for (const auto& [image_id, pose] : poses) {
      const auto it = shared.find(image_id);
      if (it == shared.end()) continue;
      std::vector<std::pair<int, uint32_t>> ranked;  // (-shared, id): most shared first, ties by id
      for (const auto& [other, count] : it->second)
        if (count >= options.min_shared_tracks) ranked.emplace_back(-count, other);
      std::sort(ranked.begin(), ranked.end());
      LocalMotion m;
      m.image_ids.push_back(image_id);
      for (size_t r = 0; r < ranked.size() && m.num_views() < options.views; r += stride)
        m.image_ids.push_back(ranked[r].second);
      if (m.num_views() < 3) continue;
      std::vector<uint32_t> key = m.image_ids;
      std::sort(key.begin(), key.end());
      if (!seen.insert(key).second) continue;
      for (const uint32_t id : m.image_ids) m.local_poses.push_back(poses.at(id));
      m.track_ids = TracksOfViews(per_image, m.image_ids);
      motions.push_back(std::move(m));
    }
  }
  return motions;
}

void ConvergeLocalMotions(const Reconstruction& tracks, const LocalHessianOptions& lh_options,
                          const LocalMotionOptions& options, std::vector<LocalMotion>* motions) {
  tbb::parallel_for(size_t(0), motions->size(), [&](size_t i) {
    LocalMotion& m = (*motions)[i];
    LocalBundleProblem problem;
    if (BuildLocalBundleProblem(tracks, m, lh_options, &problem) != LocalHessianStatus::kOk) return;
    if (!SolveLocalBundle(options.solver, &problem, /*fix_gauge=*/true)) return;
    for (int k = 0; k < m.num_views(); ++k) m.local_poses[k] = problem.poses[k].ToPose();
  });
}

std::vector<LocalMotion> ChooseLocalMotions(const Reconstruction& tracks, const std::map<uint32_t, Pose>& poses,
                                            const std::vector<LocalMotion>& triplets, const LocalMotionOptions& options) {
  switch (options.kind) {
    case MotionKind::kWholeTracks:
      return SelectWholeTrackMotions(tracks, poses, {options.max_views, options.min_tracks});
    case MotionKind::kTriplets:
      return triplets;
    case MotionKind::kNeighbours:
      return SelectLocalMotions(tracks, poses, options);
  }
  return {};
}

std::vector<LocalMotion> BuildLocalMotions(const Reconstruction& tracks, const std::map<uint32_t, Pose>& poses,
                                           const std::vector<LocalMotion>& triplets,
                                           const LocalHessianOptions& lh_options, const LocalMotionOptions& options) {
  std::vector<LocalMotion> motions = ChooseLocalMotions(tracks, poses, triplets, options);
  if (NeedsConvergedStart(options)) ConvergeLocalMotions(tracks, lh_options, options, &motions);
  if (options.kind != MotionKind::kTriplets) {
    size_t largest = 0, views = 0;
    for (const LocalMotion& m : motions) largest = std::max<size_t>(largest, m.image_ids.size());
    for (const LocalMotion& m : motions) views += m.image_ids.size();
    PGBA_LOG_DEBUG << "local motions: " << motions.size() << " motions over " << poses.size() << " images ("
                  << (motions.empty() ? 0.0 : static_cast<double>(views) / motions.size()) << " views on average, "
                  << largest << " at most)";
  }
  return motions;
}

std::string LocalMotionOptions::Check() const {
  return CheckRanges(*this, "local_motions");
}

}  // namespace pgba
