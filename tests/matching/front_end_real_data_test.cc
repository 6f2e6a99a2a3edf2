// The image front end on real photographs with ground-truth poses (shared/datasets):
// features -> exhaustive matching -> OpenGV verification, then every verified pair's
// relative rotation is compared with the one implied by the ground-truth poses.
#include <gtest/gtest.h>

#include <filesystem>
#include <set>

#include "features/extract_features.h"
#include "matching/match_images.h"
#include "pgba/geometry/rotation.h"
#include "pgba/io/colmap_text.h"
#include "pgba/util/timer.h"
#include "tests/support/shared_data.h"
#include "triplets/pair_estimation.h"

namespace pgba {
namespace {
namespace fs = std::filesystem;

struct RealDataCase {
  const char* dataset;
  int max_image_size;  // downscaling keeps the test within ~1 minute on 2 cores
  int max_features;    // (the defaults are 3200 and 8192)
  size_t min_verified_pairs;
};

class FrontEndRealData : public ::testing::TestWithParam<RealDataCase> {};

TEST_P(FrontEndRealData, VerifiedRelativeRotationsMatchGroundTruth) {
  const RealDataCase c = GetParam();
  const fs::path root = fs::path(PGBA_SHARED_DIR) / "datasets" / c.dataset;
  PGBA_NEED_SHARED_DATA(fs::exists(root / "images"), root.string());
  const fs::path ws =
      fs::temp_directory_path() / ("pgba_front_" + std::string(c.dataset) + "_" + std::to_string(::getpid()));
  fs::remove_all(ws);

  Timer timer;
  FeatureExtractionOptions fopt;
  fopt.sift.max_image_size = c.max_image_size;
  fopt.sift.max_features = c.max_features;
  const FeatureExtractionResult fr = ExtractFeatures((root / "images").string(), {}, ws.string(), fopt);
  const double t_features = timer.Seconds();
  const MatchingResult mr = MatchImages(ws.string(), MatchingOptions{});
  const double t_matching = timer.Seconds() - t_features;

  const Reconstruction gt = ReadColmapText((root / "gt").string(), /*points_optional=*/true);
  ASSERT_EQ(fr.index.images.size(), gt.images.size());
  EXPECT_TRUE(fr.skipped.empty());

  std::vector<double> errors;
  for (const TwoViewGeometry& g : mr.two_view_geometries) {
    const Image& a = gt.images.at(*gt.FindImageByName(mr.tracks.images.at(g.image_id1).name));
    const Image& b = gt.images.at(*gt.FindImageByName(mr.tracks.images.at(g.image_id2).name));
    const Eigen::Matrix3d R_21_gt = b.pose.R() * a.pose.R().transpose();
    errors.push_back(RotationAngleDeg(g.R_21, R_21_gt));
  }
  ASSERT_GE(errors.size(), c.min_verified_pairs);
  std::sort(errors.begin(), errors.end());
  const double median = errors[errors.size() / 2];
  const size_t above_5deg = std::count_if(errors.begin(), errors.end(), [](double e) { return e > 5.0; });
  std::cout << c.dataset << ": " << mr.two_view_geometries.size() << "/" << mr.num_pairs
            << " pairs verified, rotation error median " << median << " deg, max " << errors.back() << " deg, "
            << above_5deg << " above 5 deg; " << mr.track_stats.num_tracks << " tracks; features " << t_features
            << " s, matching " << t_matching << " s" << std::endl;
  EXPECT_LT(median, 1.0);
  EXPECT_LE(above_5deg, errors.size() / 10);  // gross failures are rare

  // The triplet stage's view graph starts from the front end's geometries instead of
  // estimating the pairs again from the tracks (PairOptions::front_end "refine", the
  // default): every candidate pair the front end verified is refined from its pose without
  // RANSAC, and the resulting rotations are as close to the ground truth as re-estimated ones.
  auto median_error = [&](const std::vector<TwoViewGeometry>& pairs) {
    std::vector<double> e;
    for (const TwoViewGeometry& g : pairs) {
      const Image& a = gt.images.at(*gt.FindImageByName(mr.tracks.images.at(g.image_id1).name));
      const Image& b = gt.images.at(*gt.FindImageByName(mr.tracks.images.at(g.image_id2).name));
      e.push_back(RotationAngleDeg(g.R_21, b.pose.R() * a.pose.R().transpose()));
    }
    std::sort(e.begin(), e.end());
    return e.empty() ? 1e9 : e[e.size() / 2];
  };
  PairStats estimated_stats, reused_stats;
  const auto estimated = EstimatePairs(mr.tracks, PairOptions{}, &estimated_stats);
  const auto reused = EstimatePairs(mr.tracks, PairOptions{}, &reused_stats, &mr.two_view_geometries);
  EXPECT_EQ(estimated_stats.pairs_front_end, 0);
  EXPECT_GE(static_cast<size_t>(reused_stats.pairs_front_end), mr.two_view_geometries.size() * 9 / 10);
  EXPECT_EQ(reused_stats.pairs_ransac, reused_stats.pairs_estimated - reused_stats.pairs_front_end +
                                           reused_stats.pairs_refine_fallback);
  std::cout << c.dataset << ": view graph re-estimated " << estimated.size() << " pairs in " << estimated_stats.seconds
            << " s, median rotation error " << median_error(estimated) << " deg; from the front end " << reused.size()
            << " (" << reused_stats.pairs_front_end << " refined from its pose) in " << reused_stats.seconds << " s, "
            << median_error(reused) << " deg" << std::endl;
  EXPECT_GE(reused.size(), estimated.size() * 9 / 10);
  EXPECT_LE(median_error(reused), 1.1 * median_error(estimated));

  // The tracks model is consistent and no track holds two features of one image.
  EXPECT_EQ(mr.tracks.CheckConsistency(), "");
  EXPECT_GT(mr.track_stats.num_tracks, 1000u);
  for (const auto& [id, p] : mr.tracks.points3D) {
    std::set<uint32_t> seen;
    for (const TrackElement& e : p.track) ASSERT_TRUE(seen.insert(e.image_id).second) << "track " << id;
  }
  for (const auto& [id, im] : mr.tracks.images) EXPECT_FALSE(im.points2D.empty()) << im.name;
  fs::remove_all(ws);
}

INSTANTIATE_TEST_SUITE_P(Datasets, FrontEndRealData,
                         ::testing::Values(RealDataCase{"fountain_p11", 1600, 4000, 40},
                                           RealDataCase{"temple_sparse_ring", 3200, 8192, 20}),
                         [](const auto& info) { return std::string(info.param.dataset); });

}  // namespace
}  // namespace pgba
