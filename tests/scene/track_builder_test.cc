// Tracks from matches against tracks known by construction: random ground-truth tracks are
// scattered over images with shuffled feature indices, every pairwise match they imply is
// fed in shuffled order, and the union-find must return exactly the ground-truth tracks.
#include "pgba/scene/track_builder.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>

#include "pgba/util/error.h"

namespace pgba {
namespace {

struct Scenario {
  std::map<uint32_t, Camera> cameras;
  std::vector<KeypointImage> images;
  std::vector<PairMatches> pairs;
  // Ground truth: each track as a set of (image id, keypoint xy) observations.
  std::set<std::set<std::pair<uint32_t, std::pair<double, double>>>> tracks;
};

Scenario MakeScenario(int num_images, int num_tracks, uint32_t seed) {
  std::mt19937 rng(seed);
  Scenario s;
  Camera cam;
  cam.camera_id = 7;
  cam.params = {100, 100, 50, 50};
  cam.width = cam.height = 100;
  s.cameras[7] = cam;
  // Which images see each track (at least 2), and a feature slot per observation.
  std::vector<std::vector<uint32_t>> seen(num_tracks);
  std::vector<int> count(num_images, 0);
  for (int t = 0; t < num_tracks; ++t) {
    for (int i = 0; i < num_images; ++i)
      if (rng() % 2) seen[t].push_back(i);
    while (seen[t].size() < 2) {
      const uint32_t i = rng() % num_images;
      if (std::find(seen[t].begin(), seen[t].end(), i) == seen[t].end()) seen[t].push_back(i);
    }
    for (uint32_t i : seen[t]) ++count[i];
  }
  // Unmatched distractor keypoints too, then shuffle each image's keypoint order.
  std::vector<std::vector<int>> perm(num_images);
  for (int i = 0; i < num_images; ++i) {
    KeypointImage im;
    im.image_id = 10 + 3 * i;  // non-contiguous ids
    im.name = "im" + std::to_string(i);
    im.camera_id = 7;
    const int n = count[i] + 5;
    for (int k = 0; k < n; ++k) im.keypoints.emplace_back(i * 1000 + k, k);
    perm[i].resize(n);
    std::iota(perm[i].begin(), perm[i].end(), 0);
    std::shuffle(perm[i].begin(), perm[i].end(), rng);
    s.images.push_back(im);
  }
  std::vector<int> next(num_images, 0);
  std::map<std::pair<int, int>, PairMatches> pm;
  for (int t = 0; t < num_tracks; ++t) {
    std::vector<std::pair<uint32_t, uint32_t>> obs;  // (image index, feature index)
    std::set<std::pair<uint32_t, std::pair<double, double>>> truth;
    for (uint32_t i : seen[t]) {
      const uint32_t f = perm[i][next[i]++];
      obs.emplace_back(i, f);
      const Eigen::Vector2d& xy = s.images[i].keypoints[f];
      truth.insert({s.images[i].image_id, {xy.x(), xy.y()}});
    }
    s.tracks.insert(truth);
    // A spanning set of matches is enough for union-find; use all pairs, either direction.
    for (size_t a = 0; a < obs.size(); ++a)
      for (size_t b = a + 1; b < obs.size(); ++b) {
        auto [ia, fa] = obs[a];
        auto [ib, fb] = obs[b];
        if (rng() % 2) std::swap(ia, ib), std::swap(fa, fb);
        PairMatches& p = pm[{ia, ib}];
        p.image_id1 = s.images[ia].image_id;
        p.image_id2 = s.images[ib].image_id;
        p.matches.emplace_back(fa, fb);
      }
  }
  for (auto& [k, p] : pm) {
    std::shuffle(p.matches.begin(), p.matches.end(), rng);
    s.pairs.push_back(p);
  }
  std::shuffle(s.pairs.begin(), s.pairs.end(), rng);
  return s;
}

std::set<std::set<std::pair<uint32_t, std::pair<double, double>>>> TracksOf(const Reconstruction& rec) {
  std::set<std::set<std::pair<uint32_t, std::pair<double, double>>>> out;
  for (const auto& [id, p] : rec.points3D) {
    std::set<std::pair<uint32_t, std::pair<double, double>>> t;
    for (const TrackElement& e : p.track) {
      const Eigen::Vector2d& xy = rec.images.at(e.image_id).points2D.at(e.point2D_idx).xy;
      t.insert({e.image_id, {xy.x(), xy.y()}});
    }
    out.insert(t);
  }
  return out;
}

TEST(TrackBuilder, RecoversGroundTruthTracks) {
  const Scenario s = MakeScenario(6, 300, 1);
  TrackStats stats;
  const Reconstruction rec = BuildTracks(s.cameras, s.images, s.pairs, {}, &stats);
  EXPECT_EQ(rec.CheckConsistency(), "");
  EXPECT_EQ(rec.images.size(), 6u);
  EXPECT_EQ(stats.num_tracks, 300u);
  EXPECT_EQ(stats.num_conflicting, 0u);
  EXPECT_TRUE(TracksOf(rec) == s.tracks);
  // points2D hold only tracked keypoints (the 5 distractors per image are gone).
  size_t obs = 0;
  for (const auto& [id, im] : rec.images) {
    for (const Point2D& p : im.points2D) EXPECT_NE(p.point3D_id, kNoPoint3D);
    obs += im.points2D.size();
  }
  EXPECT_EQ(obs, rec.NumObservations());
}

TEST(TrackBuilder, IndependentOfPairOrder) {
  Scenario s = MakeScenario(5, 100, 2);
  const Reconstruction a = BuildTracks(s.cameras, s.images, s.pairs, {});
  std::reverse(s.pairs.begin(), s.pairs.end());
  for (PairMatches& p : s.pairs) std::reverse(p.matches.begin(), p.matches.end());
  const Reconstruction b = BuildTracks(s.cameras, s.images, s.pairs, {});
  ASSERT_EQ(a.points3D.size(), b.points3D.size());
  for (const auto& [id, p] : a.points3D) {
    const auto& q = b.points3D.at(id);
    ASSERT_EQ(p.track.size(), q.track.size());
    for (size_t k = 0; k < p.track.size(); ++k) {
      EXPECT_EQ(p.track[k].image_id, q.track[k].image_id);
      EXPECT_EQ(p.track[k].point2D_idx, q.track[k].point2D_idx);
    }
  }
}

TEST(TrackBuilder, DropsTracksWithTwoFeaturesOfOneImage) {
  std::map<uint32_t, Camera> cams;
  cams[1].camera_id = 1;
  std::vector<KeypointImage> images(3);
  for (uint32_t i = 0; i < 3; ++i) {
    images[i].image_id = i + 1;
    images[i].camera_id = 1;
    for (int k = 0; k < 4; ++k) images[i].keypoints.emplace_back(k, i);
  }
  // Track A: 1:0 - 2:0 - 3:0 (clean). Track B: 1:1 - 2:1 - 3:1 - 1:2 (closes back onto
  // image 1 with another feature: inconsistent). Track C: 2:3 - 3:3 (clean, length 2).
  const std::vector<PairMatches> pairs = {{1, 2, {{0, 0}, {1, 1}}}, {2, 3, {{0, 0}, {1, 1}, {3, 3}}}, {3, 1, {{1, 2}}}};
  TrackStats stats;
  const Reconstruction rec = BuildTracks(cams, images, pairs, {}, &stats);
  EXPECT_EQ(stats.num_tracks, 2u);
  EXPECT_EQ(stats.num_conflicting, 1u);
  for (const auto& [id, p] : rec.points3D) {
    std::set<uint32_t> ids;
    for (const auto& e : p.track) EXPECT_TRUE(ids.insert(e.image_id).second) << "duplicate image in track";
  }
  // Ids follow the smallest node: track A (1:0) first, then C (2:3).
  ASSERT_EQ(rec.points3D.size(), 2u);
  EXPECT_EQ(rec.points3D.at(1).track.size(), 3u);
  EXPECT_EQ(rec.points3D.at(2).track.size(), 2u);
  EXPECT_EQ(rec.images.at(1).points2D.size(), 1u);
  // min_track_length 3 drops C as short.
  TrackBuilderOptions opt;
  opt.min_track_length = 3;
  const Reconstruction rec3 = BuildTracks(cams, images, pairs, opt, &stats);
  EXPECT_EQ(stats.num_tracks, 1u);
  EXPECT_EQ(stats.num_short, 1u);
}

TEST(TrackBuilder, BadMatchesAreInputErrors) {
  std::map<uint32_t, Camera> cams;
  cams[1].camera_id = 1;
  std::vector<KeypointImage> images(2);
  images[0].image_id = 1;
  images[1].image_id = 2;
  images[0].camera_id = images[1].camera_id = 1;
  images[0].keypoints.resize(3);
  images[1].keypoints.resize(3);
  EXPECT_THROW(BuildTracks(cams, images, {{1, 2, {{0, 3}}}}, {}), InputError);  // out of range
  EXPECT_THROW(BuildTracks(cams, images, {{1, 5, {{0, 0}}}}, {}), InputError);  // unknown image
  images[1].camera_id = 9;
  EXPECT_THROW(BuildTracks(cams, images, {{1, 2, {{0, 0}}}}, {}), InputError);  // unknown camera
}

}  // namespace
}  // namespace pgba
