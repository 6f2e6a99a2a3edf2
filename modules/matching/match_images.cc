#include "matching/match_images.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <map>
#include <set>
#include <sstream>

#include <filesystem>

#include "pgba/io/option_ranges.h"
#include "features/feature_file.h"
#include "features/feature_index.h"
#include "matching/third_view_transfer.h"
#include "pgba/io/colmap_text.h"
#include "pgba/io/two_view_geometries.h"
#include "pgba/util/atomic_file.h"
#include "pgba/util/error.h"
#include "pgba/util/logging.h"
#include "pgba/util/progress.h"
#include "pgba/util/text_format.h"
#include "pgba/util/cpu_time.h"
#include "pgba/util/timer.h"

namespace pgba {
namespace {

constexpr uint64_t kCascadeHashingSeed = 20140623;

// Pairs grouped into chunks whose images fit in `max_images` kd-forests: pairs are ordered
// by (block of i, block of j) with blocks of max_images / 2 images, then cut greedily.
std::vector<std::vector<ImagePair>> ChunkPairs(std::vector<ImagePair> pairs, int max_images) {
  const uint32_t block = static_cast<uint32_t>(std::max(1, max_images / 2));
  std::sort(pairs.begin(), pairs.end(), [&](const ImagePair& a, const ImagePair& b) {
    const auto ka = std::make_tuple(a.first / block, a.second / block, a.first, a.second);
    const auto kb = std::make_tuple(b.first / block, b.second / block, b.first, b.second);
    return ka < kb;
  });
  std::vector<std::vector<ImagePair>> chunks;
  std::set<uint32_t> images;
  for (const ImagePair& p : pairs) {
    const size_t extra = !images.count(p.first) + !images.count(p.second);
    if (chunks.empty() || images.size() + extra > static_cast<size_t>(std::max(2, max_images))) {
      chunks.emplace_back();
      images.clear();
    }
    chunks.back().push_back(p);
    images.insert(p.first);
    images.insert(p.second);
  }
  return chunks;
}

// Number of tracks seen by both images of each pair.
std::map<std::pair<uint32_t, uint32_t>, int> CoVisibleTracks(const Reconstruction& rec) {
  std::map<std::pair<uint32_t, uint32_t>, int> count;
  for (const auto& [id, p] : rec.points3D)
    for (size_t a = 0; a < p.track.size(); ++a)
      for (size_t b = a + 1; b < p.track.size(); ++b)
        ++count[{std::min(p.track[a].image_id, p.track[b].image_id),
                 std::max(p.track[a].image_id, p.track[b].image_id)}];
  return count;
}

// The kept pairs (verified or weak) as the triangle stages see them, and their slots.
std::vector<PairEstimate> KeptPairs(const std::vector<std::optional<VerifiedPair>>& verified,
                                    const std::vector<PairCheck>& checks, std::vector<size_t>* slots) {
  std::vector<PairEstimate> estimates;
  slots->clear();
  for (size_t k = 0; k < verified.size(); ++k) {
    if (!verified[k]) continue;
    const TwoViewGeometry& g = verified[k]->geometry;
    estimates.push_back({g.image_id1, g.image_id2, g.R_21, g.t_21, verified[k]->inlier_matches,
                         checks[k].verdict == "weak"});
    slots->push_back(k);
  }
  return estimates;
}

// Weak pairs (verdict "weak") become "confirmed" when a triangle confirms them
// (triplet_confirmation.h), "leaf" when kept as an image's only link, else "unconfirmed"
// and dropped.
void SettleWeakPairs(const TripletConfirmationOptions& options, std::vector<std::optional<VerifiedPair>>* verified,
                     std::vector<PairCheck>* checks) {
  std::vector<size_t> slot;
  const std::vector<PairEstimate> estimates = KeptPairs(*verified, *checks, &slot);
  const std::vector<int64_t> third = ConfirmWeakPairs(estimates, options);
  int confirmed = 0, leaf = 0, weak = 0;
  for (size_t e = 0; e < estimates.size(); ++e) {
    if (!estimates[e].weak) continue;
    ++weak;
    PairCheck& c = (*checks)[slot[e]];
    if (third[e] >= 0) {
      c.verdict = "confirmed";
      ++confirmed;
    } else if (third[e] == kLeafPair) {
      c.verdict = "leaf";
      ++leaf;
    } else {
      c.verdict = "unconfirmed";
      (*verified)[slot[e]].reset();
    }
  }
  PGBA_LOG_DEBUG << "matching: " << confirmed << " of " << weak << " weak pairs confirmed by a third view, " << leaf
                << " kept as an image's only link";
}

// Matches transferred into third views (third_view_transfer.h) join the kept pairs' inliers.
void TransferMatches(const FeatureIndex& index, const std::vector<FeatureSet>& features,
                     const VerificationOptions& options, const std::vector<PairCheck>& checks,
                     std::vector<std::optional<VerifiedPair>>* verified) {
  std::vector<size_t> slot;
  std::vector<PairEstimate> estimates = KeptPairs(*verified, checks, &slot);
  std::vector<std::vector<Eigen::Vector3d>> bearings(index.images.size());
  std::map<uint32_t, TransferView> views;
  double focal = 0.0, detection_scale = 1.0;
  for (size_t i = 0; i < index.images.size(); ++i) {
    const IndexedImage& im = index.images[i];
    const Camera& camera = index.cameras.at(im.camera_id);
    bearings[i] = KeypointBearings(camera, features[i].keypoints);
    views[im.image_id] = {&bearings[i], &features[i].descriptors};
    focal += camera.MeanFocal() / static_cast<double>(index.images.size());
    detection_scale = std::max(detection_scale, im.detection_scale);
  }
  GuidedMatchingOptions guided = options.guided;
  guided.threshold_px *= detection_scale;
  const std::vector<int> added = TransferIntoThirdViews(&estimates, views, focal, guided);
  int total = 0;
  for (size_t e = 0; e < estimates.size(); ++e) {
    (*verified)[slot[e]]->inlier_matches = std::move(estimates[e].matches);
    total += added[e];
  }
  PGBA_LOG_DEBUG << "matching: " << total << " matches transferred into third views";
}

}  // namespace

MatchingResult MatchImages(const std::string& workspace, const MatchingOptions& options) {
  Timer timer;
  const FeatureIndex index = ReadFeatureIndex(workspace);
  const int n = static_cast<int>(index.images.size());
  if (n < 2) ThrowInputError(FeaturesDir(workspace), 0, "fewer than two images with features");

  // All features: keypoints are small; descriptors (128 B each) are needed by retrieval and
  // to build the forests.
  std::vector<FeatureSet> features(n);
  tbb::parallel_for(0, n,
                    [&](int i) { features[i] = ReadFeatureFile(FeatureFilePath(workspace, index.images[i].name)); });
  std::vector<cv::Mat> descriptors(n);
  for (int i = 0; i < n; ++i) descriptors[i] = features[i].descriptors;

  ValidateDescriptorMatchOptions(options.descriptors);
  const std::string guided_problem = options.verification.guided.Check();
  if (!guided_problem.empty()) throw InputError("matching.verification.guided." + guided_problem);
  const std::string weak_problem = options.verification.weak_pairs.Check();
  if (!weak_problem.empty()) throw InputError("matching.verification.weak_pairs." + weak_problem);
  MatchingResult result;
  result.descriptor_method = options.descriptors.method;
  const std::vector<ImagePair> pairs = SelectPairs(descriptors, options.pairs);
  result.num_pairs = pairs.size();
  PGBA_LOG_DEBUG << "matching: " << n << " images, " << pairs.size() << " pairs (" << options.pairs.method << ")";

  // Per-pair results in preallocated slots keyed by the pair's position in `pairs`.
  std::map<ImagePair, size_t> slot_of;
  for (size_t k = 0; k < pairs.size(); ++k) slot_of[pairs[k]] = k;
  std::vector<std::optional<VerifiedPair>> verified(pairs.size());
  std::vector<PairCheck> checks(pairs.size());
  // Thread time of each pair's two steps, to report where the matching time goes.
  std::vector<double> seconds_descriptors(pairs.size(), 0.0), seconds_verification(pairs.size(), 0.0);
  std::vector<double> cpu_descriptors(pairs.size(), 0.0), cpu_verification(pairs.size(), 0.0);

  Timer match_timer;
  CpuTimer match_cpu;
  // One set of random projections for the run, centred on the run's mean descriptor, so
  // that every image's codes are made once and compare with every other image's.
  std::unique_ptr<CascadeHasher> hasher;
  if (options.descriptors.method == "cascade_hashing")
    hasher = std::make_unique<CascadeHasher>(MeanDescriptor(descriptors), options.descriptors.cascade_hashing,
                                             kCascadeHashingSeed);
  ProgressBar progress("matching", pairs.size());
  std::map<uint32_t, std::unique_ptr<DescriptorIndex>> forests;
  for (const std::vector<ImagePair>& chunk : ChunkPairs(pairs, options.max_indexed_images)) {
    std::set<uint32_t> needed;
    for (const ImagePair& p : chunk) needed.insert(p.first), needed.insert(p.second);
    for (auto it = forests.begin(); it != forests.end();)
      it = needed.count(it->first) ? std::next(it) : forests.erase(it);
    std::vector<uint32_t> to_build;
    for (uint32_t i : needed)
      if (!forests.count(i)) to_build.push_back(i);
    std::vector<std::unique_ptr<DescriptorIndex>> built(to_build.size());
    tbb::parallel_for(size_t(0), to_build.size(), [&](size_t k) {
      const uint32_t i = to_build[k];
      built[k] = std::make_unique<DescriptorIndex>(descriptors[i], options.descriptors, index.images[i].image_id,
                                                   hasher.get());
    });
    for (size_t k = 0; k < to_build.size(); ++k) forests[to_build[k]] = std::move(built[k]);

    tbb::parallel_for(size_t(0), chunk.size(), [&](size_t c) {
      const auto [i, j] = chunk[c];
      const size_t slot = slot_of.at(chunk[c]);
      Timer pair_timer;
      const double cpu0 = ThreadCpuSeconds();
      const auto matches = MatchDescriptors(*forests.at(i), *forests.at(j), options.descriptors);
      seconds_descriptors[slot] = pair_timer.Seconds();
      const double cpu1 = ThreadCpuSeconds();
      cpu_descriptors[slot] = cpu1 - cpu0;
      const IndexedImage& a = index.images[i];
      const IndexedImage& b = index.images[j];
      verified[slot] = VerifyPair(a.image_id, index.cameras.at(a.camera_id), features[i], b.image_id,
                                  index.cameras.at(b.camera_id), features[j], matches, options.verification,
                                  std::max(a.detection_scale, b.detection_scale), &checks[slot]);
      seconds_verification[slot] = pair_timer.Seconds() - seconds_descriptors[slot];
      cpu_verification[slot] = ThreadCpuSeconds() - cpu1;
      progress.Increment();
    });
  }
  progress.Finish();
  forests.clear();
  if (options.verification.weak_pairs.enabled) SettleWeakPairs(options.verification.weak_pairs, &verified, &checks);
  if (options.verification.guided.transfer) TransferMatches(index, features, options.verification, checks, &verified);
  result.seconds_matching = match_timer.Seconds();
  result.cpu_seconds_matching = match_cpu.Seconds();

  // Tracks over the verified inliers, in pair order.
  std::vector<KeypointImage> images(n);
  for (int i = 0; i < n; ++i) {
    images[i].image_id = index.images[i].image_id;
    images[i].name = index.images[i].name;
    images[i].camera_id = index.images[i].camera_id;
    for (const Keypoint& k : features[i].keypoints) images[i].keypoints.emplace_back(k.x, k.y);
  }
  std::vector<PairMatches> pair_matches;
  for (size_t k = 0; k < pairs.size(); ++k) {
    result.thread_seconds_descriptors += seconds_descriptors[k];
    result.thread_seconds_verification += seconds_verification[k];
    result.cpu_seconds_descriptors += cpu_descriptors[k];
    result.cpu_seconds_verification += cpu_verification[k];
    result.num_putative += checks[k].putative;
    result.pair_outcomes.push_back({index.images[pairs[k].first].name, index.images[pairs[k].second].name, checks[k]});
    if (!verified[k]) continue;
    result.num_verified_matches += verified[k]->inlier_matches.size();
    pair_matches.push_back(
        {verified[k]->geometry.image_id1, verified[k]->geometry.image_id2, verified[k]->inlier_matches});
  }
  result.tracks =
      BuildTracks(index.cameras, images, pair_matches, options.tracks, &result.track_stats, FeaturesDir(workspace));

  const auto covisible = CoVisibleTracks(result.tracks);
  for (size_t k = 0; k < pairs.size(); ++k) {
    if (!verified[k]) continue;
    TwoViewGeometry g = verified[k]->geometry;
    const auto it = covisible.find({g.image_id1, g.image_id2});
    g.num_tracks = it == covisible.end() ? 0 : it->second;
    result.two_view_geometries.push_back(g);
  }
  for (const auto& [id, im] : result.tracks.images)
    if (im.points2D.empty()) {
      result.images_without_tracks.push_back(im.name);
      PGBA_LOG_DEBUG << im.name << ": no verified match with any other image";
    }
  result.seconds = timer.Seconds();
  PGBA_LOG_INFO << "matching: " << result.two_view_geometries.size() << " of " << pairs.size()
                << " image pairs verified, " << result.track_stats.num_tracks << " tracks (points seen in 2 or more "
                << "images), " << FormatNumber("%.1f", result.seconds) << " s";
  PGBA_LOG_DEBUG << "matching: " << result.track_stats.num_conflicting
                 << " tracks dropped for holding two features of one image";
  return result;
}

void WriteMatchingResult(const std::string& workspace, const MatchingResult& result) {
  const std::filesystem::path ws(workspace);
  std::filesystem::create_directories(ws / "matching");
  WriteTwoViewGeometries(result.two_view_geometries, (ws / "matching" / "two_view_geometries.txt").string());
  std::ostringstream table;
  table << "# Every selected pair's geometric verification (verdict: verified | few_matches | ransac_failed |\n"
           "# few_inliers | low_inlier_ratio | uncertain_rotation | confirmed | leaf | unconfirmed)\n"
           "# NAME1 NAME2 PUTATIVE INLIERS ROTATION_SD_DEG MEDIAN_TRIANGULATION_ANGLE_DEG VERDICT\n";
  for (const PairOutcome& p : result.pair_outcomes)
    table << p.name1 << " " << p.name2 << " " << p.check.putative << " " << p.check.inliers << " "
          << FormatNumber("%.4g", p.check.rotation_sd_deg) << " "
          << FormatNumber("%.3f", p.check.median_triangulation_angle_deg) << " " << p.check.verdict << "\n";
  WriteStringAtomically((ws / "matching" / "pairs.txt").string(), table.str());
  // The tracks last: what the next stage reads exists only once everything beside it is
  // written (a full disk before leaves no tracks/ that reads as this run's result).
  WriteColmapText(result.tracks, (ws / "tracks").string());
}

nlohmann::json TrackRecord(const Reconstruction& tracks, const TrackStats& st) {
  return {{"images", tracks.images.size()},
          {"tracks", st.num_tracks},
          {"observations", st.num_observations},
          {"mean_track_length", st.mean_track_length},
          {"tracks_conflicting_dropped", st.num_conflicting}};
}

nlohmann::json MatchingRecord(const MatchingResult& r) {
  nlohmann::json record = TrackRecord(r.tracks, r.track_stats);
  record["pairs"] = r.num_pairs;
  record["pairs_verified"] = r.two_view_geometries.size();
  record["putative_matches"] = r.num_putative;
  record["verified_matches"] = r.num_verified_matches;
  record["seconds_matching"] = r.seconds_matching;
  record["cpu_seconds_matching"] = r.cpu_seconds_matching;
  if (r.num_pairs > 0) {
    record["seconds_per_pair"] = r.seconds_matching / r.num_pairs;
    record["thread_seconds_per_pair_descriptors"] = r.thread_seconds_descriptors / r.num_pairs;
    record["thread_seconds_per_pair_verification"] = r.thread_seconds_verification / r.num_pairs;
    record["cpu_seconds_per_pair"] = r.cpu_seconds_matching / r.num_pairs;
    record["cpu_seconds_per_pair_descriptors"] = r.cpu_seconds_descriptors / r.num_pairs;
    record["cpu_seconds_per_pair_verification"] = r.cpu_seconds_verification / r.num_pairs;
  }
  record["descriptor_method"] = r.descriptor_method;
  record["images_without_tracks"] = r.images_without_tracks;
  nlohmann::json verdicts = nlohmann::json::object();
  for (const PairOutcome& p : r.pair_outcomes) verdicts[p.check.verdict] = verdicts.value(p.check.verdict, 0) + 1;
  record["pair_verdicts"] = verdicts;
  return record;
}

std::string MatchingOptions::Check() const {
  if (const std::string m = CheckRanges(*this, "matching"); !m.empty()) return m;
  return "";
}

}  // namespace pgba
