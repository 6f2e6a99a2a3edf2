// The image front end on a rendered scene (modules/synthetic/rendered_scene.h), whose true
// poses are exact: features -> exhaustive matching -> verification must give every image
// tracks, verify the ring neighbours including the pair that closes the loop, and recover
// relative rotations and translation directions that agree with the truth.
#include <gtest/gtest.h>

#include <filesystem>

#include "features/extract_features.h"
#include "matching/match_images.h"
#include "matching/relative_pose.h"
#include "modules/synthetic/rendered_scene.h"
#include "pgba/geometry/rotation.h"

namespace pgba {
namespace {
namespace fs = std::filesystem;

constexpr double kRadToDeg = 180.0 / M_PI;

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

TEST(FrontEndRendered, RecoversTrueRelativePosesAroundTheRing) {
  const fs::path dir = fs::temp_directory_path() / ("pgba_front_rendered_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  RenderedSceneOptions ro;
  ro.num_images = 16;
  ro.width = 480;
  ro.height = 360;
  const RenderedScene scene = RenderRoomScene(ro);
  WriteRenderedScene(scene, dir.string());

  const fs::path ws = dir / "ws";
  const FeatureExtractionResult fr = ExtractFeatures((dir / "images").string(), {}, ws.string(), {});
  ASSERT_EQ(fr.index.images.size(), 16u);
  const MatchingResult mr = MatchImages(ws.string(), MatchingOptions{});
  EXPECT_TRUE(mr.images_without_tracks.empty());
  for (const auto& [id, im] : mr.tracks.images) EXPECT_FALSE(im.points2D.empty()) << im.name;

  std::set<std::pair<uint32_t, uint32_t>> verified;
  std::vector<double> rot_err, dir_err, sampson_px;
  const Reconstruction& gt = scene.gt;
  for (const TwoViewGeometry& g : mr.two_view_geometries) {
    const Image& a = gt.images.at(*gt.FindImageByName(mr.tracks.images.at(g.image_id1).name));
    const Image& b = gt.images.at(*gt.FindImageByName(mr.tracks.images.at(g.image_id2).name));
    verified.insert({std::min(a.image_id, b.image_id), std::max(a.image_id, b.image_id)});
    const Eigen::Matrix3d R_21 = b.pose.R() * a.pose.R().transpose();
    rot_err.push_back(RotationAngleDeg(g.R_21, R_21));
    // Translation direction: centre of view 2 in view 1's frame, true vs estimated.
    const Eigen::Vector3d c21_true = a.pose.R() * (b.pose.C() - a.pose.C());
    const Eigen::Vector3d c21_est = -g.R_21.transpose() * g.t_21;
    dir_err.push_back(std::acos(std::clamp(c21_true.normalized().dot(c21_est.normalized()), -1.0, 1.0)) * kRadToDeg);
  }
  // Ring neighbours (k, k+1) all verified, including (16, 1) that closes the loop.
  for (uint32_t k = 1; k <= 16; ++k) {
    const uint32_t next = k % 16 + 1;
    EXPECT_TRUE(verified.count({std::min(k, next), std::max(k, next)})) << k << "-" << next;
  }
  ASSERT_GE(rot_err.size(), 40u);
  const double rot_median = Median(rot_err), dir_median = Median(dir_err);
  std::cout << "rendered ring: " << mr.two_view_geometries.size() << "/" << mr.num_pairs
            << " pairs verified, rotation error median " << rot_median << " deg, max "
            << *std::max_element(rot_err.begin(), rot_err.end()) << " deg; translation direction median "
            << dir_median << " deg; " << mr.track_stats.num_tracks << " tracks" << std::endl;
  EXPECT_LT(rot_median, 0.25);
  EXPECT_LT(dir_median, 1.0);
  // Gross errors are rare (pairs that share only a small planar patch are ill-conditioned).
  EXPECT_LE(std::count_if(rot_err.begin(), rot_err.end(), [](double e) { return e > 5.0; }), rot_err.size() / 10);

  // The inliers of ring neighbours fit the TRUE epipolar geometry to a fraction of a pixel:
  // the renderer, the pixel conventions and SIFT's localisation all agree.
  const Camera& cam = gt.cameras.at(1);
  for (const auto& [pid, p] : mr.tracks.points3D) {
    for (size_t u = 0; u + 1 < p.track.size(); ++u) {
      const Image& ia = mr.tracks.images.at(p.track[u].image_id);
      const Image& ib = mr.tracks.images.at(p.track[u + 1].image_id);
      const Image& a = gt.images.at(*gt.FindImageByName(ia.name));
      const Image& b = gt.images.at(*gt.FindImageByName(ib.name));
      const Eigen::Matrix3d R_21 = b.pose.R() * a.pose.R().transpose();
      const Eigen::Vector3d t_21 = (b.pose.R() * (a.pose.C() - b.pose.C())).normalized();
      const Eigen::Vector3d b1 = cam.PixelToBearing(ia.points2D[p.track[u].point2D_idx].xy);
      const Eigen::Vector3d b2 = cam.PixelToBearing(ib.points2D[p.track[u + 1].point2D_idx].xy);
      sampson_px.push_back(std::abs(SampsonAngle(R_21, t_21, b1, b2)) * cam.MeanFocal());
    }
  }
  ASSERT_GT(sampson_px.size(), 1000u);
  const double sampson_median = Median(sampson_px);
  std::cout << "track observations vs true epipolar geometry: median " << sampson_median << " px" << std::endl;
  EXPECT_LT(sampson_median, 0.3);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace pgba
