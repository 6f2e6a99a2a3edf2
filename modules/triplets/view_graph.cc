#include "modules/triplets/view_graph.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <map>
#include <set>

#include "modules/matching/opengv_rng.h"
#include "modules/triplets/track_index.h"
#include "pgba/util/logging.h"
#include "pgba/util/progress.h"
#include "pgba/util/timer.h"

namespace pgba {
namespace {

enum class PairOutcome { kKept, kNoModel, kFewInliers, kSmallAngle };

struct Candidate {
  uint32_t id1 = 0, id2 = 0;
  int shared = 0;
};

// Candidate pairs: enough shared tracks, then the per-image cap (a pair survives if it is
// among the strongest of either image).
std::vector<Candidate> SelectCandidates(const std::map<uint64_t, int>& counts, const PairOptions& o, PairStats* st) {
  std::vector<Candidate> all;
  for (const auto& [key, n] : counts) {
    if (n < o.min_shared_tracks) {
      ++st->pairs_few_shared;
      continue;
    }
    all.push_back({static_cast<uint32_t>(key >> 32), static_cast<uint32_t>(key & 0xffffffffu), n});
  }
  if (o.max_pairs_per_image <= 0) return all;
  std::map<uint32_t, std::vector<size_t>> per_image;
  for (size_t i = 0; i < all.size(); ++i) {
    per_image[all[i].id1].push_back(i);
    per_image[all[i].id2].push_back(i);
  }
  std::vector<uint8_t> keep(all.size(), 0);
  for (auto& [id, list] : per_image) {
    std::stable_sort(list.begin(), list.end(), [&](size_t a, size_t b) { return all[a].shared > all[b].shared; });
    for (size_t k = 0; k < list.size() && k < static_cast<size_t>(o.max_pairs_per_image); ++k) keep[list[k]] = 1;
  }
  std::vector<Candidate> kept;
  for (size_t i = 0; i < all.size(); ++i) {
    if (keep[i]) {
      kept.push_back(all[i]);
    } else {
      ++st->pairs_capped;
    }
  }
  return kept;
}

PairOutcome EstimatePair(const TrackIndex& index, const Candidate& c, const PairOptions& o, TwoViewGeometry* g) {
  std::vector<Eigen::Vector3d> b1, b2;
  for (const auto& [k1, k2] : index.SharedObservations(c.id1, c.id2)) {
    b1.push_back(index.Bearing(c.id1, k1));
    b2.push_back(index.Bearing(c.id2, k2));
  }
  g->image_id1 = c.id1;
  g->image_id2 = c.id2;
  g->num_tracks = static_cast<int>(b1.size());
  const double focal = 0.5 * (index.CameraOf(c.id1).MeanFocal() + index.CameraOf(c.id2).MeanFocal());
  RelativePoseOptions rp = o.relative_pose;
  rp.seed = MixSeed(o.seed, PairKey(c.id1, c.id2));
  rp.min_inliers = std::max(rp.min_inliers, o.min_inliers);
  const RelativePoseResult r = EstimateRelativePose(b1, b2, focal, rp);
  if (r.num_inliers == 0) return PairOutcome::kNoModel;
  g->R_21 = r.R_21;
  g->t_21 = r.t_21;
  g->num_inliers = r.num_inliers;
  g->median_triangulation_angle_deg = r.median_triangulation_angle_deg;
  if (!r.success || r.num_inliers < o.min_inlier_ratio * g->num_tracks) return PairOutcome::kFewInliers;
  if (r.median_triangulation_angle_deg < o.min_triangulation_angle_deg) return PairOutcome::kSmallAngle;
  return PairOutcome::kKept;
}

// A pair the front end verified: its geometry, with the shared-track count of these tracks.
PairOutcome ReusePair(const TwoViewGeometry& verified, const Candidate& c, const PairOptions& o, TwoViewGeometry* g) {
  *g = verified;
  g->num_tracks = c.shared;
  if (g->num_inliers < o.min_inliers) return PairOutcome::kFewInliers;
  if (g->median_triangulation_angle_deg < o.min_triangulation_angle_deg) return PairOutcome::kSmallAngle;
  return PairOutcome::kKept;
}

// The front end's geometries by pair key, oriented as image_id1 < image_id2.
std::map<uint64_t, TwoViewGeometry> ByPairKey(const std::vector<TwoViewGeometry>& geometries) {
  std::map<uint64_t, TwoViewGeometry> out;
  for (TwoViewGeometry g : geometries) {
    if (g.image_id1 > g.image_id2) {
      // x_1 = R_21^T x_2 - R_21^T t_21: the inverse motion, its translation renormalised.
      const Eigen::Matrix3d R_12 = g.R_21.transpose();
      const Eigen::Vector3d t_12 = -(R_12 * g.t_21);
      std::swap(g.image_id1, g.image_id2);
      g.R_21 = R_12;
      g.t_21 = t_12.normalized();
    }
    out[PairKey(g.image_id1, g.image_id2)] = g;
  }
  return out;
}

}  // namespace

nlohmann::json ToJson(const PairStats& s) {
  return {{"images", s.images},
          {"pairs_sharing_tracks", s.pairs_sharing_tracks},
          {"pairs_few_shared", s.pairs_few_shared},
          {"pairs_capped", s.pairs_capped},
          {"pairs_estimated", s.pairs_estimated},
          {"pairs_reused", s.pairs_reused},
          {"rejected_no_model", s.rejected_no_model},
          {"rejected_few_inliers", s.rejected_few_inliers},
          {"rejected_small_angle", s.rejected_small_angle},
          {"pairs_kept", s.pairs_kept},
          {"images_in_view_graph", s.images_in_view_graph},
          {"seconds", s.seconds}};
}

std::vector<TwoViewGeometry> EstimatePairs(const Reconstruction& tracks, const PairOptions& options,
                                           PairStats* stats_out, const std::vector<TwoViewGeometry>* front_end) {
  Timer timer;
  PairStats stats;
  const TrackIndex index(tracks);
  stats.images = static_cast<int>(tracks.images.size());
  const std::map<uint64_t, int> counts = index.CountSharedTracks();
  stats.pairs_sharing_tracks = static_cast<int>(counts.size());
  const std::vector<Candidate> candidates = SelectCandidates(counts, options, &stats);
  stats.pairs_estimated = static_cast<int>(candidates.size());
  const std::map<uint64_t, TwoViewGeometry> verified = front_end ? ByPairKey(*front_end) : decltype(verified){};

  // Each pair writes its own slot: the result is independent of the scheduling.
  std::vector<TwoViewGeometry> geometries(candidates.size());
  std::vector<PairOutcome> outcomes(candidates.size());
  ProgressBar progress("pairs", candidates.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, candidates.size(), 4), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      const auto it = verified.find(PairKey(candidates[i].id1, candidates[i].id2));
      outcomes[i] = it != verified.end() ? ReusePair(it->second, candidates[i], options, &geometries[i])
                                         : EstimatePair(index, candidates[i], options, &geometries[i]);
      progress.Increment();
    }
  });
  progress.Finish();

  std::vector<TwoViewGeometry> kept;
  std::set<uint32_t> images;
  for (size_t i = 0; i < candidates.size(); ++i) {
    stats.pairs_reused += verified.count(PairKey(candidates[i].id1, candidates[i].id2)) > 0;
    switch (outcomes[i]) {
      case PairOutcome::kKept:
        kept.push_back(geometries[i]);
        images.insert(candidates[i].id1);
        images.insert(candidates[i].id2);
        break;
      case PairOutcome::kNoModel: ++stats.rejected_no_model; break;
      case PairOutcome::kFewInliers: ++stats.rejected_few_inliers; break;
      case PairOutcome::kSmallAngle: ++stats.rejected_small_angle; break;
    }
  }
  stats.pairs_kept = static_cast<int>(kept.size());
  stats.images_in_view_graph = static_cast<int>(images.size());
  stats.seconds = timer.Seconds();
  PGBA_LOG_INFO << "view graph: " << stats.pairs_kept << " of " << stats.pairs_estimated << " pairs verified, "
                << stats.images_in_view_graph << "/" << stats.images << " images, " << stats.seconds << " s";
  if (stats_out) *stats_out = stats;
  return kept;
}

}  // namespace pgba
