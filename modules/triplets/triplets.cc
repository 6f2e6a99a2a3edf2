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
#include "pgba/util/text_format.h"
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

// Candidate for the images `ids` (ascending); one of the three pairs may be absent (open).
Candidate MakeCandidate(const std::array<uint32_t, 3>& ids, const std::map<uint64_t, const TwoViewGeometry*>& by_key) {
  Candidate c;
  c.ids = ids;
  auto find = [&](uint32_t a, uint32_t b) -> const TwoViewGeometry* {
    auto it = by_key.find(PairKey(a, b));
    return it == by_key.end() ? nullptr : it->second;
  };
  c.pairs = {find(ids[0], ids[1]), find(ids[0], ids[2]), find(ids[1], ids[2])};
  return c;
}

// Before estimation: a closed triplet's pair rotations must close; every triplet needs
// enough tracks, and enough seen by all three views to place its third view (absolute pose
// for a closed one, one baseline length for an open one). Sets the prior score; false (with
// the rejection set) if the candidate is not worth estimating.
bool Precheck(const TrackIndex& index, const TripletOptions& options, Candidate* c) {
  const bool open = !c->pairs[0] || !c->pairs[1] || !c->pairs[2];
  if (!open && RotationCycleDeg(*c) > options.max_rotation_cycle_deg) {
    c->estimate.rejection = TripletRejection::kRotationCycle;
    return false;
  }
  int n3 = 0, n2 = 0;
  for (const TripletTrack& t : TracksOfTriplet(index, c->ids)) {
    ++n2;
    n3 += t.NumViews() == 3;
  }
  if (n2 < options.min_tracks || n3 < (open ? options.open_min_tracks_all_views : options.absolute_pose.min_inliers)) {
    c->estimate.rejection = TripletRejection::kTooFewTracks;
    return false;
  }
  double angle = 0.0;
  for (const TwoViewGeometry* g : c->pairs)
    if (g) angle = std::max(angle, g->median_triangulation_angle_deg);
  c->prior_score = TripletScore(n3, angle, options);
  return true;
}

// Open triplets that can join what the estimated triplets leave apart (none if `kept` forms
// one component covering every image of the view graph): paths a - b - c of
// two verified pairs, (a, c) not a pair, whose two pairs lie in different components of the
// triplet graph of `kept`, or one in a component and the other in no triplet, or both in no
// triplet with an image of the path uncovered. Ascending ids, lexicographic order.
std::vector<std::array<uint32_t, 3>> BridgingPaths(const std::vector<TwoViewGeometry>& pairs,
                                                   const std::vector<std::array<uint32_t, 3>>& kept) {
  int num_components = 0;
  const std::vector<int> label_of_triplet = TripletGraphComponents(kept, &num_components);
  std::map<uint64_t, int> label;  // pair -> component of the triplets holding it
  std::set<uint32_t> covered;
  for (size_t i = 0; i < kept.size(); ++i) {
    const auto& t = kept[i];
    covered.insert(t.begin(), t.end());
    for (uint64_t e : {PairKey(t[0], t[1]), PairKey(t[0], t[2]), PairKey(t[1], t[2])}) label[e] = label_of_triplet[i];
  }
  std::map<uint32_t, std::vector<uint32_t>> neighbours;
  std::set<uint64_t> is_pair;
  for (const TwoViewGeometry& g : pairs) {
    if (g.image_id1 == g.image_id2 || !is_pair.insert(PairKey(g.image_id1, g.image_id2)).second) continue;
    neighbours[g.image_id1].push_back(g.image_id2);
    neighbours[g.image_id2].push_back(g.image_id1);
  }
  if (num_components <= 1 && covered.size() >= neighbours.size()) return {};  // nothing to bridge
  auto label_or = [&](uint32_t a, uint32_t b) {
    auto it = label.find(PairKey(a, b));
    return it == label.end() ? -1 : it->second;
  };
  std::set<std::array<uint32_t, 3>> paths;
  for (auto& [hinge, list] : neighbours) {
    std::sort(list.begin(), list.end());
    for (size_t i = 0; i < list.size(); ++i) {
      for (size_t j = i + 1; j < list.size(); ++j) {
        const uint32_t a = list[i], c = list[j];
        if (is_pair.count(PairKey(a, c))) continue;  // a triangle: not open
        // Pairs in no kept triplet are unlabelled (-1): a path of two of them can only help
        // if it covers an image that no triplet holds yet.
        const int la = label_or(a, hinge), lc = label_or(hinge, c);
        if (la < 0 && lc < 0 ? covered.count(a) && covered.count(hinge) && covered.count(c) : la == lc) continue;
        std::array<uint32_t, 3> ids{a, hinge, c};
        std::sort(ids.begin(), ids.end());
        paths.insert(ids);
      }
    }
  }
  return {paths.begin(), paths.end()};
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
          {"open_candidates", s.open_candidates},
          {"open_selected", s.open_selected},
          {"rejected_rotation_cycle", s.rejected_rotation_cycle},
          {"rejected_few_tracks_precheck", s.rejected_few_tracks_precheck},
          {"estimated", s.estimated},
          {"rejected_too_few_tracks", s.rejected_too_few_tracks},
          {"rejected_init_failed", s.rejected_init_failed},
          {"rejected_not_converged", s.rejected_not_converged},
          {"intrinsics_freed", s.intrinsics_freed},
          {"rejected_high_rms", s.rejected_high_rms},
          {"rejected_degenerate", s.rejected_degenerate},
          {"selection_rounds", s.selection_rounds},
          {"selected_unestimated", s.selected_unestimated},
          {"selected", s.selected},
          {"images_in_view_graph", s.images_in_view_graph},
          {"images_covered", s.images_covered},
          {"triplet_graph_components", s.triplet_graph_components},
          {"median_rms_px", s.median_rms_px},
          {"seconds", s.seconds}};
}

std::vector<LocalMotion> BuildTriplets(const Reconstruction& tracks, const std::vector<TwoViewGeometry>& pairs,
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
  std::vector<Candidate> candidates;
  auto add_candidates = [&](const std::vector<std::array<uint32_t, 3>>& ids_list) {
    std::vector<Candidate> all(ids_list.size());
    std::vector<uint8_t> usable(ids_list.size(), 0);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, ids_list.size(), 16), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t i = r.begin(); i != r.end(); ++i) {
        all[i] = MakeCandidate(ids_list[i], by_key);
        usable[i] = Precheck(index, options, &all[i]);
      }
    });
    for (size_t i = 0; i < all.size(); ++i) {
      if (usable[i]) {
        candidates.push_back(std::move(all[i]));
      } else if (all[i].estimate.rejection == TripletRejection::kRotationCycle) {
        ++stats.rejected_rotation_cycle;
      } else {
        ++stats.rejected_few_tracks_precheck;
      }
    }
  };
  const std::vector<std::array<uint32_t, 3>> triangles = EnumerateTriangles(pairs);
  stats.candidates = static_cast<int>(triangles.size());
  add_candidates(triangles);

  // Select -> estimate the newly selected -> select again keeping the estimated ones and
  // replacing the failures, until the selection is fully estimated.
  const int max_per_image = options.selection ? options.max_triplets_per_image : 0;
  std::vector<size_t> selected;
  int round = 0;
  auto select_and_estimate = [&] {
    for (;; ++round) {
      std::vector<TripletCandidate> view(candidates.size());
      for (size_t i = 0; i < candidates.size(); ++i) {
        view[i].image_ids = candidates[i].ids;
        view[i].excluded = candidates[i].state == State::kFailed;
        view[i].locked = candidates[i].state == State::kEstimated;
        view[i].score =
            candidates[i].state == State::kEstimated ? candidates[i].estimate.score : candidates[i].prior_score;
      }
      selected = SelectTriplets(view, max_per_image);
      std::vector<size_t> todo;
      for (size_t i : selected)
        if (candidates[i].state == State::kPending) todo.push_back(i);
      if (todo.empty()) break;
      if (round >= std::max(1, options.max_selection_rounds)) {
        stats.selected_unestimated += static_cast<int>(todo.size());
        break;
      }
      stats.selection_rounds = round + 1;
      EstimateAll(index, todo, options, round, &candidates, &stats);
    }
  };
  select_and_estimate();

  // Open triplets where the triangles leave the graph in pieces or an image uncovered.
  if (options.open_triplets) {
    std::vector<std::array<uint32_t, 3>> kept;
    for (size_t i : selected)
      if (candidates[i].state == State::kEstimated) kept.push_back(candidates[i].ids);
    const std::vector<std::array<uint32_t, 3>> paths = BridgingPaths(pairs, kept);
    stats.open_candidates = static_cast<int>(paths.size());
    if (!paths.empty()) {
      add_candidates(paths);
      select_and_estimate();
    }
  }

  std::vector<LocalMotion> result;
  std::set<uint32_t> covered;
  std::vector<double> rms;
  for (size_t i : selected) {
    if (candidates[i].state != State::kEstimated) continue;
    result.push_back(candidates[i].estimate.triplet);
    const auto& p = candidates[i].pairs;
    stats.open_selected += !p[0] || !p[1] || !p[2];
    for (uint32_t id : candidates[i].ids) covered.insert(id);
    rms.push_back(candidates[i].estimate.triplet.rms_px);
    stats.intrinsics_freed += candidates[i].estimate.intrinsics_freed;
  }
  stats.selected = static_cast<int>(result.size());
  stats.images_covered = static_cast<int>(covered.size());
  std::vector<std::array<uint32_t, 3>> ids;
  for (const LocalMotion& t : result) ids.push_back(TripletImageIds(t));
  TripletGraphComponents(ids, &stats.triplet_graph_components);
  if (!rms.empty()) {
    std::nth_element(rms.begin(), rms.begin() + rms.size() / 2, rms.end());
    stats.median_rms_px = rms[rms.size() / 2];
  }
  stats.seconds = timer.Seconds();
  PGBA_LOG_INFO << "triplets: " << stats.selected << " kept of " << stats.estimated << " estimated (from "
                << stats.candidates << (stats.candidates == 1 ? " triangle" : " triangles") << " of the view graph"
                << (stats.open_candidates ? " and " + std::to_string(stats.open_candidates) + " chains of two pairs"
                                          : "")
                << "), " << stats.images_covered << " of " << stats.images_in_view_graph << " images covered, "
                << FormatNumber("%.2f", stats.median_rms_px) << " px median RMS, " << FormatNumber("%.1f", stats.seconds)
                << " s";
  if (stats.triplet_graph_components > 1)
    PGBA_LOG_WARN << "triplets: they form " << stats.triplet_graph_components
                  << " groups that share no image pair; each is a model of its own, in its own frame and scale, "
                     "unless their points join them later (more overlap between the groups' photos joins them)";
  // Triplets still pending when the rounds ran out are left out: harmless while every image is
  // in a kept triplet (the others only add redundancy), a lost image otherwise.
  if (stats.selected_unestimated > 0) {
    const int uncovered = stats.images_in_view_graph - stats.images_covered;
    if (uncovered > 0) {
      PGBA_LOG_WARN << "triplets: the selection stopped after " << options.max_selection_rounds << " rounds with "
                    << stats.selected_unestimated << " chosen triplets not estimated, and " << uncovered
                    << " images are in no kept triplet (they cannot be registered): raise "
                       "triplets.max_selection_rounds in the config";
    } else {
      PGBA_LOG_DEBUG << "triplets: the selection stopped after " << options.max_selection_rounds << " rounds with "
                     << stats.selected_unestimated
                     << " chosen triplets not estimated; every image is in a kept triplet, so none is lost";
    }
  }
  if (stats_out) *stats_out = stats;
  return result;
}

}  // namespace pgba
