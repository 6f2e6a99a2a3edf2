#include "averaging/global_init.h"

#include <algorithm>
#include <array>
#include <set>
#include <stdexcept>

#include "pgba/io/option_ranges.h"
#include "averaging/connectivity.h"
#include "averaging/relative_rotations.h"
#include "averaging/similarity.h"
#include "pgba/geometry/rotation.h"
#include "pgba/util/error.h"
#include "pgba/util/logging.h"
#include "pgba/util/timer.h"

namespace pgba {
namespace {

std::vector<LocalMotion> Select(const std::vector<LocalMotion>& triplets, const std::vector<int>& indices) {
  std::vector<LocalMotion> out;
  out.reserve(indices.size());
  for (int t : indices) out.push_back(triplets[t]);
  return out;
}

// Keeps the triplets of the largest component; returns how many were removed.
int KeepLargestComponent(std::vector<LocalMotion>* triplets) {
  const std::vector<int> kept = LargestTripletComponent(*triplets);
  const int removed = static_cast<int>(triplets->size() - kept.size());
  *triplets = Select(*triplets, kept);
  return removed;
}

std::vector<TwoViewGeometry> PairsWithin(const std::vector<TwoViewGeometry>& pairs, const std::set<uint32_t>& images) {
  std::vector<TwoViewGeometry> out;
  for (const TwoViewGeometry& p : pairs)
    if (images.count(p.image_id1) && images.count(p.image_id2)) out.push_back(p);
  return out;
}

void CheckImageIds(const Reconstruction& tracks, const std::vector<TwoViewGeometry>& pairs,
                   const std::vector<LocalMotion>& triplets) {
  auto check = [&](uint32_t id, const std::string& what) {
    if (!tracks.images.count(id))
      throw InputError(what + " references image id " + std::to_string(id) + ", which is not in the tracks");
  };
  for (size_t p = 0; p < pairs.size(); ++p) {
    check(pairs[p].image_id1, "pair " + std::to_string(p));
    check(pairs[p].image_id2, "pair " + std::to_string(p));
  }
  for (size_t t = 0; t < triplets.size(); ++t)
    for (uint32_t id : triplets[t].image_ids) check(id, "triplet " + std::to_string(t));
}

bool IsUsable(const TwoViewGeometry& p) {
  return p.image_id1 != p.image_id2 && p.R_21.allFinite() &&
         (p.R_21 * p.R_21.transpose() - Eigen::Matrix3d::Identity()).norm() < 1e-6 && p.t_21.allFinite() &&
         p.t_21.norm() > 0.0;
}

// Distinct images, finite local poses and a non-zero baseline.
bool IsUsable(const LocalMotion& t) {
  if (!HasDistinctImages(t)) return false;
  double baseline = 0.0, magnitude = 0.0;
  for (int k = 0; k < 3; ++k) {
    if (!t.local_poses[k].q().coeffs().allFinite() || !t.local_poses[k].t().allFinite()) return false;
    baseline = std::max(baseline, (t.local_poses[k].C() - t.local_poses[(k + 1) % 3].C()).norm());
    magnitude = std::max(magnitude, t.local_poses[k].C().norm());
  }
  return baseline > 1e-9 * magnitude && baseline > 0.0;  // coincident centres up to round-off
}

}  // namespace

GlobalInitResult RunGlobalInitialisation(const Reconstruction& tracks, const std::vector<TwoViewGeometry>& pairs_in,
                                         const std::vector<LocalMotion>& triplets_in, const GlobalInitOptions& options,
                                         const std::vector<LocalMotion>* rotation_measurements) {
  ValidateRotationAveragingOptions(options.rotation);
  ValidateTranslationAveragingOptions(options.translation);
  ValidateTrackPositioningOptions(options.track_positioning);
  CheckImageIds(tracks, pairs_in, triplets_in);
  Timer total;
  GlobalInitResult result;
  GlobalInitStats& stats = result.stats;
  stats.images_input = static_cast<int>(tracks.images.size());
  stats.pairs_input = static_cast<int>(pairs_in.size());
  stats.triplets_input = static_cast<int>(triplets_in.size());

  std::vector<TwoViewGeometry> pairs;
  for (const TwoViewGeometry& p : pairs_in)
    if (IsUsable(p)) pairs.push_back(p);
  std::vector<LocalMotion> triplets;
  for (const LocalMotion& t : triplets_in)
    if (IsUsable(t)) triplets.push_back(t);
  stats.pairs_invalid = static_cast<int>(pairs_in.size() - pairs.size());
  stats.triplets_invalid = static_cast<int>(triplets_in.size() - triplets.size());
  if (stats.pairs_invalid || stats.triplets_invalid)
    PGBA_LOG_WARN << "ignoring " << stats.pairs_invalid << " invalid pairs and " << stats.triplets_invalid
                  << " invalid triplets (repeated images, non-finite values or no baseline)";
  // 1. The local poses whose relative rotations the averaging measures, by image ids (empty:
  // the triplets' own).
  std::map<std::vector<uint32_t>, std::vector<Pose>> measured_poses;
  if (rotation_measurements) {
    if (rotation_measurements->size() != triplets_in.size())
      throw std::invalid_argument("RunGlobalInitialisation: rotation measurements not aligned with the triplets");
    for (size_t k = 0; k < triplets_in.size(); ++k) {
      if ((*rotation_measurements)[k].image_ids != triplets_in[k].image_ids)
        throw std::invalid_argument("RunGlobalInitialisation: rotation measurements not aligned with the triplets");
      measured_poses[triplets_in[k].image_ids] = (*rotation_measurements)[k].local_poses;
    }
  }
  // The triplets as rotation measurements: with the corrupted relative rotations in place.
  auto as_measured = [&](const std::vector<LocalMotion>& in) {
    if (measured_poses.empty()) return in;
    std::vector<LocalMotion> out = in;
    for (LocalMotion& t : out) {
      auto it = measured_poses.find(t.image_ids);
      if (it != measured_poses.end()) t.local_poses = it->second;
    }
    return out;
  };

  auto finish = [&](bool ok, const std::string& message) {
    result.success = ok;
    result.message = message;
    for (const auto& [id, image] : tracks.images) {
      if (result.poses.count(id)) continue;
      result.dropped_image_ids.push_back(id);
      result.images_dropped.push_back(image.name);
    }
    stats.images_registered = static_cast<int>(result.poses.size());
    stats.triplets_kept = static_cast<int>(result.triplets.size());
    stats.seconds_total = total.Seconds();
    if (!result.images_dropped.empty()) {
      std::string names;
      for (const std::string& n : result.images_dropped) names += (names.empty() ? "" : ", ") + n;
      PGBA_LOG_DEBUG << "global initialisation dropped " << result.images_dropped.size() << " of "
                    << stats.images_input << " images: " << names;
    }
    if (!ok) PGBA_LOG_WARN << "global initialisation: " << message;
    return result;
  };

  // 2. Largest triplet component.
  stats.triplets_outside_component += KeepLargestComponent(&triplets);
  if (triplets.empty()) return finish(false, "no usable triplet");

  // 3. Pairs checked against the triplets (those no triplet covers: against the rotations
  // averaged from the triplets alone), then rotation averaging.
  Timer timer;
  std::set<uint32_t> images = ImagesOfTriplets(triplets, LargestTripletComponent(triplets));
  if (options.pair_validation.enabled) {
    RotationAveragingOptions triplets_only = options.rotation;
    triplets_only.observations.use_pairs = false;
    triplets_only.observations.use_triplets = true;
    std::map<uint32_t, Eigen::Matrix3d> from_triplets;
    const std::vector<LocalMotion> measured = as_measured(triplets);
    const bool ok = AverageRotations(CollectRelativeRotations({}, measured, triplets_only.observations),
                                     triplets_only, &from_triplets);
    pairs = PairsConsistentWithTriplets(pairs, measured, options.pair_validation, ok ? &from_triplets : nullptr,
                                        &stats.pairs_inconsistent);
    PGBA_LOG_DEBUG << "pair validation: " << stats.pairs_inconsistent << " pairs disagree with the triplets";
  }
  std::map<uint32_t, Eigen::Matrix3d> rotations;
  const std::vector<RelativeRotation> observations =
      CollectRelativeRotations(PairsWithin(pairs, images), as_measured(triplets), options.rotation.observations);
  {
    // Without the triplets' rotations the pairs alone may not connect the component.
    std::vector<TwoViewGeometry> graph;
    for (const RelativeRotation& o : observations) graph.push_back({o.image_id1, o.image_id2});
    const std::set<uint32_t> connected = LargestViewGraphComponent(graph);
    if (connected.size() < images.size()) {
      std::vector<int> inside;
      for (int t = 0; t < static_cast<int>(triplets.size()); ++t)
        if (connected.count(triplets[t].image_ids[0]) && connected.count(triplets[t].image_ids[1]) &&
            connected.count(triplets[t].image_ids[2]))
          inside.push_back(t);
      stats.triplets_outside_component += static_cast<int>(triplets.size() - inside.size());
      triplets = Select(triplets, inside);
      stats.triplets_outside_component += KeepLargestComponent(&triplets);
      if (triplets.empty()) return finish(false, "the relative rotations do not connect any triplet");
    }
  }
  const bool rotations_ok = AverageRotations(observations, options.rotation, &rotations, &stats.rotation);
  stats.seconds_rotation = timer.Seconds();
  if (!rotations_ok) return finish(false, "rotation averaging failed: " + stats.rotation.message);
  if (!stats.rotation.images_without_inliers.empty()) {
    // Images whose every observation is an outlier have no rotation, nor their triplets.
    std::vector<int> rotated;
    for (int t = 0; t < static_cast<int>(triplets.size()); ++t)
      if (rotations.count(triplets[t].image_ids[0]) && rotations.count(triplets[t].image_ids[1]) &&
          rotations.count(triplets[t].image_ids[2]))
        rotated.push_back(t);
    stats.triplets_outside_component += static_cast<int>(triplets.size() - rotated.size());
    triplets = Select(triplets, rotated);
    stats.triplets_outside_component += KeepLargestComponent(&triplets);
    if (triplets.empty()) return finish(false, "no triplet has inlier rotations");
  }

  // 4. Triplets inconsistent with the averaged rotations.
  if (options.max_triplet_rotation_error_deg > 0.0) {
    std::vector<int> consistent;
    for (int t = 0; t < static_cast<int>(triplets.size()); ++t) {
      const Eigen::Matrix3d alpha = AverageTripletRotation(triplets[t], rotations);
      double worst = 0.0;
      for (int k = 0; k < 3; ++k)
        worst = std::max(worst, RotationAngleDeg(triplets[t].local_poses[k].R(),
                                                 rotations.at(triplets[t].image_ids[k]) * alpha.transpose()));
      if (worst <= options.max_triplet_rotation_error_deg) consistent.push_back(t);
    }
    stats.triplets_rotation_outliers = static_cast<int>(triplets.size() - consistent.size());
    triplets = Select(triplets, consistent);
    stats.triplets_outside_component += KeepLargestComponent(&triplets);
    if (triplets.empty()) return finish(false, "no triplet agrees with the averaged rotations");
  }

  // 5. Translation averaging.
  timer.Restart();
  images = ImagesOfTriplets(triplets, LargestTripletComponent(triplets));
  std::map<uint32_t, Eigen::Vector3d> centres;
  const bool centres_ok =
      AverageTranslations(triplets, PairsWithin(pairs, images), rotations, options.translation, &centres,
                          &stats.translation);
  stats.seconds_translation = timer.Seconds();
  if (!centres_ok) return finish(false, "translation averaging failed: " + stats.translation.message);
  std::map<uint32_t, Pose> poses;
  for (uint32_t id : images) poses[id] = Pose::FromRC(rotations.at(id), centres.at(id));
  if (options.track_positioning.enabled) {
    timer.Restart();
    if (!PositionOnTracks(tracks, triplets, options.track_positioning, &poses, &stats.track_positioning) &&
        !stats.track_positioning.message.empty())
      PGBA_LOG_DEBUG << "track positioning skipped: " << stats.track_positioning.message;
    stats.seconds_translation += timer.Seconds();
  }

  // 6. Similarities; triplets whose centres do not fit are dropped.
  timer.Restart();
  const std::vector<TripletSimilarityFit> fits = ComputeTripletSimilarities(poses, &triplets);
  std::vector<int> fitting;
  for (int t = 0; t < static_cast<int>(triplets.size()); ++t)
    if (fits[t].valid &&
        (options.max_triplet_centre_error <= 0.0 || fits[t].centre_residual_rel <= options.max_triplet_centre_error))
      fitting.push_back(t);
  stats.triplets_centre_outliers = static_cast<int>(triplets.size() - fitting.size());
  triplets = Select(triplets, fitting);
  stats.triplets_outside_component += KeepLargestComponent(&triplets);
  stats.seconds_similarity = timer.Seconds();
  if (triplets.empty()) return finish(false, "no triplet fits the averaged poses");

  for (uint32_t id : ImagesOfTriplets(triplets, LargestTripletComponent(triplets))) result.poses[id] = poses.at(id);
  result.triplets = std::move(triplets);
  PGBA_LOG_DEBUG << "global initialisation: " << result.poses.size() << " images, " << result.triplets.size()
                << " triplets kept of " << stats.triplets_input << " (" << stats.triplets_outside_component
                << " outside the component, " << stats.triplets_rotation_outliers << " rotation outliers, "
                << stats.triplets_centre_outliers << " centre outliers)";
  return finish(true, "ok");
}

std::vector<GlobalInitResult> InitialiseComponents(const Reconstruction& tracks,
                                                   const std::vector<TwoViewGeometry>& pairs,
                                                   const std::vector<LocalMotion>& triplets,
                                                   const GlobalInitOptions& options,
                                                   const std::vector<LocalMotion>* rotation_measurements) {
  if (rotation_measurements && rotation_measurements->size() != triplets.size())
    throw std::invalid_argument("InitialiseComponents: rotation measurements not aligned with the triplets");
  CheckImageIds(tracks, pairs, triplets);
  const std::vector<std::vector<int>> components = TripletComponents(triplets);
  std::vector<GlobalInitResult> results;
  for (const std::vector<int>& component : components) {
    const std::set<uint32_t> images = ImagesOfTriplets(triplets, component);
    std::vector<LocalMotion> measured;
    if (rotation_measurements) measured = Select(*rotation_measurements, component);
    PGBA_LOG_DEBUG << "triplet component " << results.size() << ": " << images.size() << " images, "
                  << component.size() << " triplets";
    results.push_back(RunGlobalInitialisation(tracks, PairsWithin(pairs, images), Select(triplets, component), options,
                                              rotation_measurements ? &measured : nullptr));
  }
  if (results.empty()) results.push_back(RunGlobalInitialisation(tracks, pairs, {}, options));
  std::stable_sort(results.begin(), results.end(), [](const GlobalInitResult& a, const GlobalInitResult& b) {
    if (a.success != b.success) return a.success;
    return a.poses.size() > b.poses.size();
  });
  return results;
}

nlohmann::json GlobalInitReport(const GlobalInitResult& result) {
  const GlobalInitStats& s = result.stats;
  nlohmann::json j;
  j["success"] = result.success;
  j["message"] = result.message;
  j["seconds"] = s.seconds_total;
  j["seconds_rotation"] = s.seconds_rotation;
  j["seconds_translation"] = s.seconds_translation;
  j["seconds_similarity"] = s.seconds_similarity;
  j["images_input"] = s.images_input;
  j["images_registered"] = s.images_registered;
  j["images_dropped"] = result.images_dropped;
  j["pairs_input"] = s.pairs_input;
  j["triplets_input"] = s.triplets_input;
  j["triplets_kept"] = s.triplets_kept;
  j["pairs_invalid"] = s.pairs_invalid;
  j["pairs_inconsistent"] = s.pairs_inconsistent;
  j["triplets_dropped"] = {{"invalid", s.triplets_invalid},
                           {"outside_component", s.triplets_outside_component},
                           {"rotation_outlier", s.triplets_rotation_outliers},
                           {"centre_outlier", s.triplets_centre_outliers}};
  j["rotation"] = {{"observations", s.rotation.num_observations},
                   {"seconds", s.rotation.seconds},
                   {"inliers", s.rotation.num_inliers},
                   {"outliers", s.rotation.num_outliers},
                   {"tree_edges_validated", s.rotation.tree_validated},
                   {"images_without_inliers", s.rotation.images_without_inliers.size()},
                   {"l1_iterations", s.rotation.l1_iterations},
                   {"irls_iterations", s.rotation.irls_iterations},
                   {"converged", s.rotation.converged},
                   {"residual_median_deg", s.rotation.residual_median_deg}};
  j["translation"] = {{"triplets", s.translation.num_triplets},
                      {"pair_directions", s.translation.num_pairs},
                      {"scale_links", s.translation.scale_links},
                      {"refine_iterations", s.translation.refine_iterations},
                      {"seconds_scales", s.translation.seconds_scales},
                      {"seconds_centres", s.translation.seconds_centres},
                      {"seconds_refine", s.translation.seconds_refine},
                      {"residual_median_rel", s.translation.residual_median_rel}};
  j["track_positioning"] = {{"ran", s.track_positioning.ran},
                            {"message", s.track_positioning.message},
                            {"points", s.track_positioning.num_points},
                            {"observations", s.track_positioning.num_observations},
                            {"iterations", s.track_positioning.iterations},
                            {"initial_rms_px", s.track_positioning.initial_rms_px},
                            {"final_rms_px", s.track_positioning.final_rms_px},
                            {"seconds", s.track_positioning.seconds}};
  return j;
}

std::string GlobalInitOptions::Check() const {
  if (const std::string m = CheckRanges(*this, "global_init"); !m.empty()) return m;
  // Cross-field rules of the parts (the ranges of every part are checked above).
  if (const std::string p = rotation.Check(); !p.empty()) return "rotation." + p;
  return "";
}

}  // namespace pgba
