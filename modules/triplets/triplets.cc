#include "modules/triplets/triplets.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <map>
#include <set>

#include "modules/matching/opengv_rng.h"
#include "modules/triplets/track_index.h"
#include "modules/triplets/triplet_estimation.h"
#include "modules/triplets/triplet_selection.h"
#include "pgba/geometry/rotation.h"
#include "pgba/util/logging.h"
#include "pgba/util/progress.h"
#include "pgba/util/timer.h"

namespace pgba {
namespace {

enum class State { kPending, kEstimated, kFailed };

struct Candidate {
  std::array<uint32_t, 3> ids{};
  std::array<const TwoViewGeometry*, 3> pairs{};  // (0,1), (0,2), (1,2)
  double prior_score = 0.0;
  State state = State::kPending;
  TripletEstimate estimate;
};

// Angle (deg) by which the three pair rotations fail to close: R_20 vs R_21 R_10.
double RotationCycleDeg(const Candidate& c) {
  const Eigen::Matrix3d R10 = RelativePoseOfPair(*c.pairs[0], c.ids[0], c.ids[1]).R();
  const Eigen::Matrix3d R20 = RelativePoseOfPair(*c.pairs[1], c.ids[0], c.ids[2]).R();
  const Eigen::Matrix3d R21 = RelativePoseOfPair(*c.pairs[2], c.ids[1], c.ids[2]).R();
  return RotationAngleDeg(R21 * R10, R20);
}

void Count(TripletRejection r, TripletStats* s) {
  switch (r) {
    case TripletRejection::kNone: break;
    case TripletRejection::kRotationCycle: ++s->rejected_rotation_cycle; break;
    case TripletRejection::kTooFewTracks: ++s->rejected_too_few_tracks; break;
    case TripletRejection::kInitFailed: ++s->rejected_init_failed; break;
    case TripletRejection::kNotConverged: ++s->rejected_not_converged; break;
    case TripletRejection::kHighRms: ++s->rejected_high_rms; break;
    case TripletRejection::kDegenerate: ++s->rejected_degenerate; break;
  }
}

// Estimates the listed candidates in parallel, each into its own slot.
void EstimateAll(const TrackIndex& index, const std::vector<size_t>& todo, const TripletOptions& options, int round,
                 std::vector<Candidate>* candidates, TripletStats* stats) {
  ProgressBar progress(round == 0 ? "triplets" : "triplets (round " + std::to_string(round + 1) + ")", todo.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, todo.size(), 1), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t k = r.begin(); k != r.end(); ++k) {
      Candidate& c = (*candidates)[todo[k]];
      const uint64_t key = (static_cast<uint64_t>(c.ids[0]) * 0x100000001b3ULL) ^ PairKey(c.ids[1], c.ids[2]);
      c.estimate = EstimateTriplet(index, c.ids, c.pairs, options, MixSeed(options.seed, key));
      c.state = c.estimate.rejection == TripletRejection::kNone ? State::kEstimated : State::kFailed;
      progress.Increment();
    }
  });
  progress.Finish();
  for (size_t i : todo) {
    ++stats->estimated;
    Count((*candidates)[i].estimate.rejection, stats);
  }
}

}  // namespace

std::vector<std::array<uint32_t, 3>> EnumerateTriangles(const std::vector<TwoViewGeometry>& pairs) {
  std::map<uint32_t, std::vector<uint32_t>> higher;  // neighbours with a larger id, sorted
  for (const TwoViewGeometry& g : pairs) {
    const uint32_t a = std::min(g.image_id1, g.image_id2), b = std::max(g.image_id1, g.image_id2);
    if (a != b) higher[a].push_back(b);
  }
  for (auto& [id, list] : higher) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
  std::vector<std::array<uint32_t, 3>> triangles;
  for (const auto& [a, na] : higher) {
    for (uint32_t b : na) {
      auto it = higher.find(b);
      if (it == higher.end()) continue;
      // c > b adjacent to both a and b: intersection of the two sorted lists.
      const auto& nb = it->second;
      for (size_t i = 0, j = 0; i < na.size() && j < nb.size();) {
        if (na[i] < nb[j]) {
          ++i;
        } else if (nb[j] < na[i]) {
          ++j;
        } else {
          triangles.push_back({a, b, na[i]});
          ++i;
          ++j;
        }
      }
    }
  }
  return triangles;
}

nlohmann::json ToJson(const TripletStats& s) {
  return {{"candidates", s.candidates},
          {"rejected_rotation_cycle", s.rejected_rotation_cycle},
          {"rejected_few_tracks_precheck", s.rejected_few_tracks_precheck},
          {"estimated", s.estimated},
          {"rejected_too_few_tracks", s.rejected_too_few_tracks},
          {"rejected_init_failed", s.rejected_init_failed},
          {"rejected_not_converged", s.rejected_not_converged},
          {"rejected_high_rms", s.rejected_high_rms},
          {"rejected_degenerate", s.rejected_degenerate},
          {"selection_rounds", s.selection_rounds},
          {"selected", s.selected},
          {"images_in_view_graph", s.images_in_view_graph},
          {"images_covered", s.images_covered},
          {"triplet_graph_components", s.triplet_graph_components},
          {"median_rms_px", s.median_rms_px},
          {"seconds", s.seconds}};
}

std::vector<Triplet> BuildTriplets(const Reconstruction& tracks, const std::vector<TwoViewGeometry>& pairs,
                                   const TripletOptions& options, TripletStats* stats_out) {
  Timer timer;
  TripletStats stats;
  const TrackIndex index(tracks);
  std::map<uint64_t, const TwoViewGeometry*> by_key;
  std::set<uint32_t> graph_images;
  for (const TwoViewGeometry& g : pairs) {
    by_key[PairKey(g.image_id1, g.image_id2)] = &g;
    graph_images.insert(g.image_id1);
    graph_images.insert(g.image_id2);
  }
  stats.images_in_view_graph = static_cast<int>(graph_images.size());

  // Candidates: consistent rotation cycle, enough shared tracks; prior score for selection.
  const std::vector<std::array<uint32_t, 3>> triangles = EnumerateTriangles(pairs);
  stats.candidates = static_cast<int>(triangles.size());
  std::vector<Candidate> all(triangles.size());
  std::vector<uint8_t> usable(triangles.size(), 0);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, triangles.size(), 16), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      Candidate& c = all[i];
      c.ids = triangles[i];
      c.pairs = {by_key.at(PairKey(c.ids[0], c.ids[1])), by_key.at(PairKey(c.ids[0], c.ids[2])),
                 by_key.at(PairKey(c.ids[1], c.ids[2]))};
      if (RotationCycleDeg(c) > options.max_rotation_cycle_deg) {
        c.estimate.rejection = TripletRejection::kRotationCycle;
        continue;
      }
      int n3 = 0, n2 = 0;
      for (const TripletTrack& t : TracksOfTriplet(index, c.ids)) {
        ++n2;
        n3 += t.NumViews() == 3;
      }
      if (n2 < options.min_tracks || n3 < options.absolute_pose.min_inliers) {
        c.estimate.rejection = TripletRejection::kTooFewTracks;
        continue;
      }
      double angle = 0.0;
      for (const TwoViewGeometry* g : c.pairs) angle = std::max(angle, g->median_triangulation_angle_deg);
      c.prior_score = TripletScore(n3, angle, options);
      usable[i] = 1;
    }
  });
  std::vector<Candidate> candidates;
  for (size_t i = 0; i < all.size(); ++i) {
    if (usable[i]) {
      candidates.push_back(std::move(all[i]));
    } else if (all[i].estimate.rejection == TripletRejection::kRotationCycle) {
      ++stats.rejected_rotation_cycle;
    } else {
      ++stats.rejected_few_tracks_precheck;
    }
  }

  // Select -> estimate the newly selected -> select again keeping the estimated ones and
  // replacing the failures, until the selection is fully estimated.
  const int max_per_image = options.selection ? options.max_triplets_per_image : 0;
  std::vector<size_t> selected;
  for (int round = 0;; ++round) {
    std::vector<TripletCandidate> view(candidates.size());
    for (size_t i = 0; i < candidates.size(); ++i) {
      view[i].image_ids = candidates[i].ids;
      view[i].excluded = candidates[i].state == State::kFailed;
      view[i].locked = candidates[i].state == State::kEstimated;
      view[i].score = candidates[i].state == State::kEstimated ? candidates[i].estimate.score : candidates[i].prior_score;
    }
    selected = SelectTriplets(view, max_per_image);
    std::vector<size_t> todo;
    for (size_t i : selected)
      if (candidates[i].state == State::kPending) todo.push_back(i);
    if (todo.empty()) break;
    if (round >= std::max(1, options.max_selection_rounds)) {
      PGBA_LOG_WARN << "triplet selection: " << todo.size() << " selected triplets left unestimated after "
                    << round << " rounds";
      break;
    }
    stats.selection_rounds = round + 1;
    EstimateAll(index, todo, options, round, &candidates, &stats);
  }

  std::vector<Triplet> result;
  std::set<uint32_t> covered;
  std::vector<double> rms;
  for (size_t i : selected) {
    if (candidates[i].state != State::kEstimated) continue;
    result.push_back(candidates[i].estimate.triplet);
    for (uint32_t id : candidates[i].ids) covered.insert(id);
    rms.push_back(candidates[i].estimate.triplet.rms_px);
  }
  stats.selected = static_cast<int>(result.size());
  stats.images_covered = static_cast<int>(covered.size());
  std::vector<std::array<uint32_t, 3>> ids;
  for (const Triplet& t : result) ids.push_back(t.image_ids);
  TripletGraphComponents(ids, &stats.triplet_graph_components);
  if (!rms.empty()) {
    std::nth_element(rms.begin(), rms.begin() + rms.size() / 2, rms.end());
    stats.median_rms_px = rms[rms.size() / 2];
  }
  stats.seconds = timer.Seconds();
  PGBA_LOG_INFO << "triplets: " << stats.selected << " kept of " << stats.candidates << " candidates ("
                << stats.estimated << " estimated), " << stats.images_covered << "/" << stats.images_in_view_graph
                << " images covered, " << stats.triplet_graph_components << " component(s), " << stats.seconds
                << " s";
  if (stats_out) *stats_out = stats;
  return result;
}

}  // namespace pgba
