#include "modules/triplets/pair_estimation.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <map>
#include <set>
#include <stdexcept>

#include "pgba/io/option_ranges.h"
#include "modules/matching/opengv_rng.h"
#include "modules/triplets/track_index.h"
#include "pgba/util/logging.h"
#include "pgba/util/progress.h"
#include "pgba/util/text_format.h"
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
// `verified` (may be null): the front end's pairs; without track_only_pairs only they are
// candidates, before the cap so that its slots go to them.
std::vector<Candidate> SelectCandidates(const std::map<uint64_t, int>& counts, const PairOptions& o,
                                        const std::map<uint64_t, TwoViewGeometry>* verified, PairStats* st) {
  std::vector<Candidate> all;
  for (const auto& [key, n] : counts) {
    if (n < o.min_shared_tracks) {
      ++st->pairs_few_shared;
      continue;
    }
    if (verified && !o.track_only_pairs && !verified->count(key)) {
      ++st->pairs_track_only_skipped;
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

// The shared tracks' bearings of a candidate, and the focal that converts the pixel
// threshold to an angle.
struct PairCorrespondences {
  std::vector<Eigen::Vector3d> b1, b2;
  double focal = 0.0;
};
PairCorrespondences CorrespondencesOf(const TrackIndex& index, const Candidate& c) {
  PairCorrespondences out;
  for (const auto& [k1, k2] : index.SharedObservations(c.id1, c.id2)) {
    out.b1.push_back(index.Bearing(c.id1, k1));
    out.b2.push_back(index.Bearing(c.id2, k2));
  }
  out.focal = 0.5 * (index.CameraOf(c.id1).MeanFocal() + index.CameraOf(c.id2).MeanFocal());
  return out;
}

RelativePoseOptions PoseOptionsOf(const Candidate& c, const PairOptions& o) {
  RelativePoseOptions rp = o.relative_pose;
  rp.seed = MixSeed(o.seed, PairKey(c.id1, c.id2));
  rp.min_inliers = std::max(rp.min_inliers, o.min_inliers);
  return rp;
}

// The tests every estimated or refined pair passes.
PairOutcome Judge(const RelativePoseResult& r, const PairCorrespondences& pc, const Candidate& c,
                  const PairOptions& o, TwoViewGeometry* g) {
  g->image_id1 = c.id1;
  g->image_id2 = c.id2;
  g->num_tracks = static_cast<int>(pc.b1.size());
  if (r.num_inliers == 0) return PairOutcome::kNoModel;
  g->R_21 = r.R_21;
  g->t_21 = r.t_21;
  g->num_inliers = r.num_inliers;
  g->median_triangulation_angle_deg = r.median_triangulation_angle_deg;
  if (!r.success || r.num_inliers < o.min_inlier_ratio * g->num_tracks) return PairOutcome::kFewInliers;
  if (r.median_triangulation_angle_deg < o.min_triangulation_angle_deg) return PairOutcome::kSmallAngle;
  return PairOutcome::kKept;
}

PairOutcome EstimatePair(const PairCorrespondences& pc, const Candidate& c, const PairOptions& o,
                         TwoViewGeometry* g) {
  return Judge(EstimateRelativePose(pc.b1, pc.b2, pc.focal, PoseOptionsOf(c, o)), pc, c, o, g);
}

// A pair the front end verified, refined from its pose on the tracks' correspondences (which
// may differ from its matches: tracks merged through third images, conflicts dropped).
PairOutcome RefinePair(const PairCorrespondences& pc, const TwoViewGeometry& verified, const Candidate& c,
                       const PairOptions& o, TwoViewGeometry* g) {
  return Judge(RefineRelativePose(pc.b1, pc.b2, pc.focal, PoseOptionsOf(c, o), verified.R_21, verified.t_21), pc, c,
               o, g);
}

// A pair the front end verified: its geometry, with the shared-track count of these tracks.
PairOutcome ReusePair(const TwoViewGeometry& verified, const Candidate& c, const PairOptions& o, TwoViewGeometry* g) {
  *g = verified;
  g->num_tracks = c.shared;
  if (g->num_inliers < o.min_inliers) return PairOutcome::kFewInliers;
  if (g->median_triangulation_angle_deg < o.min_triangulation_angle_deg) return PairOutcome::kSmallAngle;
  return PairOutcome::kKept;
}

// How one candidate was decided (for the stats).
enum class PairPath { kRansac, kReused, kRefined, kRefineFallback };

PairOutcome DecidePair(const TrackIndex& index, const TwoViewGeometry* verified, const Candidate& c,
                       const PairOptions& o, TwoViewGeometry* g, PairPath* path) {
  if (verified && o.front_end == "reuse") {
    *path = PairPath::kReused;
    return ReusePair(*verified, c, o, g);
  }
  const PairCorrespondences pc = CorrespondencesOf(index, c);
  if (verified && o.front_end == "refine") {
    *path = PairPath::kRefined;
    const PairOutcome outcome = RefinePair(pc, *verified, c, o, g);
    if (outcome == PairOutcome::kKept) return outcome;
    *path = PairPath::kRefineFallback;  // the tracks disagree with the front end's pose
  } else {
    *path = PairPath::kRansac;
  }
  return EstimatePair(pc, c, o, g);
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

std::string PairOptions::Check() const {
  if (const std::string m = CheckRanges(*this, "pairs"); !m.empty()) return m;
  if (front_end != "refine" && front_end != "reuse" && front_end != "estimate")
    return "front_end must be one of refine, reuse, estimate (got '" + front_end + "')";
  return "";
}

nlohmann::json ToJson(const PairStats& s) {
  return {{"images", s.images},
          {"pairs_sharing_tracks", s.pairs_sharing_tracks},
          {"pairs_few_shared", s.pairs_few_shared},
          {"pairs_capped", s.pairs_capped},
          {"pairs_track_only_skipped", s.pairs_track_only_skipped},
          {"pairs_estimated", s.pairs_estimated},
          {"pairs_front_end", s.pairs_front_end},
          {"pairs_reused", s.pairs_reused},
          {"pairs_refined", s.pairs_refined},
          {"pairs_refine_fallback", s.pairs_refine_fallback},
          {"pairs_ransac", s.pairs_ransac},
          {"rejected_no_model", s.rejected_no_model},
          {"rejected_few_inliers", s.rejected_few_inliers},
          {"rejected_small_angle", s.rejected_small_angle},
          {"pairs_kept", s.pairs_kept},
          {"pairs_kept_front_end", s.pairs_kept_front_end},
          {"pairs_kept_ransac", s.pairs_kept_ransac},
          {"images_in_view_graph", s.images_in_view_graph},
          {"seconds", s.seconds}};
}

std::vector<TwoViewGeometry> EstimatePairs(const Reconstruction& tracks, const PairOptions& options,
                                           PairStats* stats_out, const std::vector<TwoViewGeometry>* front_end) {
  const std::string problem = options.Check();
  if (!problem.empty()) throw std::invalid_argument("PairOptions: " + problem);
  Timer timer;
  PairStats stats;
  const TrackIndex index(tracks);
  stats.images = static_cast<int>(tracks.images.size());
  const std::map<uint64_t, int> counts = index.CountSharedTracks();
  stats.pairs_sharing_tracks = static_cast<int>(counts.size());
  // "estimate" ignores the front end altogether (the view graph of a tracks model alone).
  const bool use_front_end = front_end && options.front_end != "estimate";
  const std::map<uint64_t, TwoViewGeometry> verified = use_front_end ? ByPairKey(*front_end) : decltype(verified){};
  const std::vector<Candidate> candidates =
      SelectCandidates(counts, options, use_front_end ? &verified : nullptr, &stats);
  stats.pairs_estimated = static_cast<int>(candidates.size());

  // Each pair writes its own slot: the result is independent of the scheduling.
  std::vector<TwoViewGeometry> geometries(candidates.size());
  std::vector<PairOutcome> outcomes(candidates.size());
  std::vector<PairPath> paths(candidates.size());
  ProgressBar progress("pairs", candidates.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, candidates.size(), 4), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      const auto it = verified.find(PairKey(candidates[i].id1, candidates[i].id2));
      outcomes[i] = DecidePair(index, it != verified.end() ? &it->second : nullptr, candidates[i], options,
                               &geometries[i], &paths[i]);
      progress.Increment();
    }
  });
  progress.Finish();

  std::vector<TwoViewGeometry> kept;
  std::set<uint32_t> images;
  for (size_t i = 0; i < candidates.size(); ++i) {
    stats.pairs_front_end += paths[i] != PairPath::kRansac;
    stats.pairs_reused += paths[i] == PairPath::kReused;
    stats.pairs_refined += paths[i] == PairPath::kRefined || paths[i] == PairPath::kRefineFallback;
    stats.pairs_refine_fallback += paths[i] == PairPath::kRefineFallback;
    stats.pairs_ransac += paths[i] == PairPath::kRansac || paths[i] == PairPath::kRefineFallback;
    switch (outcomes[i]) {
      case PairOutcome::kKept:
        kept.push_back(geometries[i]);
        ++(paths[i] == PairPath::kReused || paths[i] == PairPath::kRefined ? stats.pairs_kept_front_end
                                                                           : stats.pairs_kept_ransac);
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
  const int rejected = stats.pairs_estimated - stats.pairs_kept;
  PGBA_LOG_INFO << "view graph: " << stats.pairs_kept << " image pairs verified of " << stats.pairs_estimated
                << " sharing tracks (" << stats.pairs_kept_front_end << " with the matching's geometry, "
                << stats.pairs_kept_ransac << " by RANSAC on the tracks), " << stats.images_in_view_graph << " of "
                << stats.images << " images connected, " << FormatNumber("%.1f", stats.seconds) << " s";
  PGBA_LOG_DEBUG << "view graph: " << rejected << " pairs rejected (" << stats.rejected_no_model << " no relative pose, "
                 << stats.rejected_few_inliers << " too few inliers, " << stats.rejected_small_angle
                 << " baseline too short for their depth); " << stats.pairs_few_shared << " pairs sharing fewer than "
                 << options.min_shared_tracks << " tracks and " << stats.pairs_capped
                 << " beyond the per-image limit not examined";
  if (stats_out) *stats_out = stats;
  return kept;
}

}  // namespace pgba
