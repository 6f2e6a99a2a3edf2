#include "benchmark/triplet_split_tracks.h"

#include <gtest/gtest.h>

namespace pgba {
namespace {

// Four images; track A seen by all four, track B by images 1 and 4 only.
Reconstruction FourViews() {
  Reconstruction r;
  Camera cam;
  cam.camera_id = 1;
  cam.model = CameraModel::kSimplePinhole;
  cam.width = 100;
  cam.height = 100;
  cam.params = {100.0, 50.0, 50.0};
  r.cameras[1] = cam;
  for (uint32_t id = 1; id <= 4; ++id) {
    Image im;
    im.image_id = id;
    im.name = "im" + std::to_string(id);
    im.camera_id = 1;
    im.points2D.resize(2);
    im.points2D[0].xy = Eigen::Vector2d(10.0 * id, 1.0);  // track A
    im.points2D[1].xy = Eigen::Vector2d(10.0 * id, 2.0);  // track B (images 1 and 4)
    r.images[id] = im;
  }
  r.AddPoint3D(Eigen::Vector3d(0, 0, 5), {{1, 0}, {2, 0}, {3, 0}, {4, 0}});
  r.AddPoint3D(Eigen::Vector3d(0, 1, 5), {{1, 1}, {4, 1}});
  return r;
}

LocalMotion TripletOf(uint32_t a, uint32_t b, uint32_t c) {
  LocalMotion t;
  t.image_ids = {a, b, c};
  return t;
}

TEST(SplitTracksByTriplets, OnePointPerTripletAndTrackWithCopiedObservations) {
  const Reconstruction tracks = FourViews();
  const Reconstruction split = SplitTracksByTriplets(tracks, {TripletOf(1, 2, 3), TripletOf(2, 3, 4)});
  EXPECT_EQ(split.CheckConsistency(), "");
  // Track A gives one point per triplet (3 views each); track B keeps only 1 view in each
  // triplet, so it gives none, and leaves no stray copy behind.
  ASSERT_EQ(split.points3D.size(), 2u);
  for (const auto& [id, p] : split.points3D) {
    EXPECT_EQ(p.track.size(), 3u);
    for (const TrackElement& e : p.track) {
      const Point2D& copy = split.images.at(e.image_id).points2D.at(e.point2D_idx);
      EXPECT_EQ(copy.xy, tracks.images.at(e.image_id).points2D[0].xy);
      EXPECT_EQ(copy.point3D_id, static_cast<int64_t>(id));
    }
  }
  // Images 2 and 3 are in both triplets: two copies each; 1 and 4 one each. The original
  // observations stay, unassigned.
  EXPECT_EQ(split.images.at(1).points2D.size(), 3u);
  EXPECT_EQ(split.images.at(2).points2D.size(), 4u);
  EXPECT_EQ(split.images.at(3).points2D.size(), 4u);
  EXPECT_EQ(split.images.at(4).points2D.size(), 3u);
  for (const auto& [id, im] : split.images) {
    EXPECT_EQ(im.points2D[0].point3D_id, kNoPoint3D);
    EXPECT_EQ(im.points2D[1].point3D_id, kNoPoint3D);
  }
}

}  // namespace
}  // namespace pgba
