// Reconstruction bookkeeping: observations and tracks stay linked both ways through
// AddPoint3D / DeletePoint3D / KeepImages, and CheckConsistency finds every broken link.
#include "pgba/scene/reconstruction.h"

#include <gtest/gtest.h>

#include <stdexcept>

namespace pgba {
namespace {

// Camera 1, images 10, 20, 30 with 4 unlinked observations each.
Reconstruction MakeScene() {
  Reconstruction rec;
  Camera cam;
  cam.camera_id = 1;
  cam.model = CameraModel::kSimplePinhole;
  cam.width = 640;
  cam.height = 480;
  cam.params = {500, 320, 240};
  rec.cameras[1] = cam;
  for (uint32_t id : {10u, 20u, 30u}) {
    Image im;
    im.image_id = id;
    im.camera_id = 1;
    im.name = "img_" + std::to_string(id) + ".jpg";
    im.points2D.resize(4);
    for (int k = 0; k < 4; ++k) im.points2D[k].xy = Eigen::Vector2d(10.0 * k, id);
    rec.images[id] = im;
  }
  return rec;
}

TEST(Reconstruction, AddPoint3DLinksBothWays) {
  Reconstruction rec = MakeScene();
  EXPECT_EQ(rec.CheckConsistency(), "");
  const uint64_t a = rec.AddPoint3D(Eigen::Vector3d(1, 2, 3), {{10, 0}, {20, 1}, {30, 2}});
  const uint64_t b = rec.AddPoint3D(Eigen::Vector3d(4, 5, 6), {{10, 3}, {30, 0}});
  EXPECT_EQ(a, 1u);
  EXPECT_EQ(b, 2u);
  EXPECT_EQ(rec.points3D.at(a).point3D_id, a);
  EXPECT_EQ(rec.points3D.at(a).xyz, Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(rec.images.at(10).points2D[0].point3D_id, static_cast<int64_t>(a));
  EXPECT_EQ(rec.images.at(20).points2D[1].point3D_id, static_cast<int64_t>(a));
  EXPECT_EQ(rec.images.at(30).points2D[0].point3D_id, static_cast<int64_t>(b));
  EXPECT_EQ(rec.images.at(20).points2D[0].point3D_id, kNoPoint3D);
  EXPECT_EQ(rec.NumObservations(), 5u);
  EXPECT_EQ(rec.CheckConsistency(), "");
  // Ids continue after the largest one, even after deleting in the middle.
  rec.points3D[100].point3D_id = 100;
  EXPECT_EQ(rec.AddPoint3D(Eigen::Vector3d::Zero(), {}), 101u);
}

TEST(Reconstruction, AddPoint3DRejectsBadTrackWithoutSideEffects) {
  Reconstruction rec = MakeScene();
  const Reconstruction before = rec;
  // Second element refers to a missing image / observation: nothing may be linked.
  EXPECT_THROW(rec.AddPoint3D(Eigen::Vector3d::Zero(), {{10, 0}, {99, 0}}), std::out_of_range);
  EXPECT_THROW(rec.AddPoint3D(Eigen::Vector3d::Zero(), {{10, 0}, {20, 4}}), std::out_of_range);
  EXPECT_EQ(rec.images.at(10).points2D[0].point3D_id, kNoPoint3D);
  EXPECT_TRUE(rec.points3D.empty());
  // An observation already linked to another point cannot be stolen silently.
  rec.AddPoint3D(Eigen::Vector3d::Zero(), {{10, 0}, {20, 0}});
  EXPECT_THROW(rec.AddPoint3D(Eigen::Vector3d::Zero(), {{30, 0}, {20, 0}}), std::invalid_argument);
  // Nor can a track list the same observation twice.
  EXPECT_THROW(rec.AddPoint3D(Eigen::Vector3d::Zero(), {{30, 1}, {30, 1}}), std::invalid_argument);
  EXPECT_EQ(rec.points3D.size(), 1u);
  EXPECT_EQ(rec.images.at(30).points2D[0].point3D_id, kNoPoint3D);
  EXPECT_EQ(rec.CheckConsistency(), "");
}

TEST(Reconstruction, DeletePoint3DUnlinks) {
  Reconstruction rec = MakeScene();
  const uint64_t a = rec.AddPoint3D(Eigen::Vector3d(1, 2, 3), {{10, 0}, {20, 1}, {30, 2}});
  const uint64_t b = rec.AddPoint3D(Eigen::Vector3d(4, 5, 6), {{10, 3}, {30, 0}});
  rec.DeletePoint3D(a);
  EXPECT_EQ(rec.points3D.count(a), 0u);
  EXPECT_EQ(rec.images.at(10).points2D[0].point3D_id, kNoPoint3D);
  EXPECT_EQ(rec.images.at(20).points2D[1].point3D_id, kNoPoint3D);
  EXPECT_EQ(rec.images.at(30).points2D[2].point3D_id, kNoPoint3D);
  EXPECT_EQ(rec.images.at(10).points2D[3].point3D_id, static_cast<int64_t>(b));
  EXPECT_EQ(rec.NumObservations(), 2u);
  EXPECT_EQ(rec.CheckConsistency(), "");
  rec.DeletePoint3D(12345);  // absent: no-op
  EXPECT_EQ(rec.points3D.size(), 1u);
}

TEST(Reconstruction, KeepImagesDropsTracksBelowTwoViews) {
  Reconstruction rec = MakeScene();
  const uint64_t a = rec.AddPoint3D(Eigen::Vector3d(1, 2, 3), {{10, 0}, {20, 1}, {30, 2}});
  const uint64_t b = rec.AddPoint3D(Eigen::Vector3d(4, 5, 6), {{10, 3}, {30, 0}});
  const uint64_t c = rec.AddPoint3D(Eigen::Vector3d(7, 8, 9), {{20, 2}, {30, 3}});
  rec.KeepImages({10, 20});
  EXPECT_EQ(rec.images.size(), 2u);
  EXPECT_EQ(rec.images.count(30), 0u);
  ASSERT_EQ(rec.points3D.count(a), 1u);
  EXPECT_EQ(rec.points3D.at(a).track.size(), 2u);
  EXPECT_EQ(rec.points3D.count(b), 0u);  // one view left
  EXPECT_EQ(rec.points3D.count(c), 0u);
  EXPECT_EQ(rec.images.at(10).points2D[3].point3D_id, kNoPoint3D);  // b's remaining view unlinked
  EXPECT_EQ(rec.images.at(20).points2D[2].point3D_id, kNoPoint3D);
  EXPECT_EQ(rec.cameras.size(), 1u);
  EXPECT_EQ(rec.CheckConsistency(), "");
  EXPECT_EQ(rec.FindImageByName("img_20.jpg"), std::optional<uint32_t>(20));
  EXPECT_EQ(rec.FindImageByName("img_30.jpg"), std::nullopt);
  rec.KeepImages({});
  EXPECT_TRUE(rec.images.empty());
  EXPECT_TRUE(rec.points3D.empty());
  EXPECT_EQ(rec.CheckConsistency(), "");
}

// Each kind of broken link is found and described.
TEST(Reconstruction, CheckConsistencyFindsEveryBrokenLink) {
  Reconstruction base = MakeScene();
  const uint64_t a = base.AddPoint3D(Eigen::Vector3d(1, 2, 3), {{10, 0}, {20, 1}});
  ASSERT_EQ(base.CheckConsistency(), "");
  auto expect_problem = [](const Reconstruction& rec, const std::string& needle) {
    const std::string p = rec.CheckConsistency();
    EXPECT_NE(p.find(needle), std::string::npos) << "got '" << p << "', expected '" << needle << "'";
  };
  {
    Reconstruction rec = base;
    rec.images.at(20).camera_id = 5;
    expect_problem(rec, "refers to missing camera 5");
  }
  {
    Reconstruction rec = base;
    rec.images.at(30).points2D[1].point3D_id = 77;
    expect_problem(rec, "refers to missing point 77");
  }
  {
    Reconstruction rec = base;
    rec.images.at(30).points2D[1].point3D_id = static_cast<int64_t>(a);  // not in a's track
    expect_problem(rec, "does not list image 30 observation 1");
  }
  {
    Reconstruction rec = base;
    rec.points3D.at(a).track.push_back({40, 0});
    expect_problem(rec, "refers to missing image 40");
  }
  {
    Reconstruction rec = base;
    rec.points3D.at(a).track.push_back({30, 9});
    expect_problem(rec, "refers to observation 9 beyond the 4 of image 30");
  }
  {
    Reconstruction rec = base;
    rec.points3D.at(a).track.push_back({30, 1});  // observation not linked back
    expect_problem(rec, "does not point back to point");
  }
  {
    Reconstruction rec = base;
    rec.points3D.at(a).track.push_back({10, 0});  // same element twice
    expect_problem(rec, "twice");
  }
  {
    Reconstruction rec = base;
    rec.points3D.at(a).point3D_id = a + 1;  // key and stored id disagree
    expect_problem(rec, "holds point3D_id");
  }
  {
    Reconstruction rec = base;
    rec.images.at(20).image_id = 21;
    expect_problem(rec, "holds image_id 21");
  }
  {
    Reconstruction rec = base;
    rec.cameras.at(1).camera_id = 2;
    expect_problem(rec, "holds camera_id 2");
  }
}

}  // namespace
}  // namespace pgba
