// Tanks and Temples .log trajectories: camera-to-world matrices to our world->camera poses
// (checked on hand-computed values), strict parsing, round trip, and the conversion of a
// hand-made scene into the dataset layout.
#include "pgba/io/trajectory_log.h"

#include <gtest/gtest.h>

#include "pgba/io/colmap_text.h"
#include "pgba/io/tanks_and_temples.h"
#include "pgba/util/error.h"
#include "tests/io/dataset_test_dir.h"

namespace pgba {
namespace {

using TrajectoryLogTest = testing::TempDirTest;

// Frame 0: identity rotation at C = (1, 2, 3). Frame 1: camera x axis = world y, camera y
// axis = -world x (90 degrees about z), centre (0, 0, 5).
const char* kLog =
    "0 0 0\n"
    "1 0 0 1\n"
    "0 1 0 2\n"
    "0 0 1 3\n"
    "0 0 0 1\n"
    "1 1 0\n"
    "0 -1 0 0\n"
    "1 0 0 0\n"
    "0 0 1 5\n"
    "0 0 0 1\n";

TEST_F(TrajectoryLogTest, CameraToWorldBecomesWorldToCameraPose) {
  const std::vector<TrajectoryFrame> f = ReadTrajectoryLog(Write("a.log", kLog));
  ASSERT_EQ(f.size(), 2u);
  EXPECT_EQ(f[1].header, (std::array<int64_t, 3>{1, 1, 0}));
  EXPECT_EQ(f[1].line, 6);
  const Pose p0 = f[0].ToPose(), p1 = f[1].ToPose();
  EXPECT_NEAR((p0.C() - Eigen::Vector3d(1, 2, 3)).norm(), 0, 1e-15);
  EXPECT_NEAR((p0.ToCamera(Eigen::Vector3d(1, 2, 4)) - Eigen::Vector3d(0, 0, 1)).norm(), 0, 1e-15);
  EXPECT_NEAR((p1.C() - Eigen::Vector3d(0, 0, 5)).norm(), 0, 1e-15);
  // World point one unit along world x from the centre: camera y = -world x, so (0, -1, 0).
  EXPECT_NEAR((p1.ToCamera(Eigen::Vector3d(1, 0, 5)) - Eigen::Vector3d(0, -1, 0)).norm(), 0, 1e-15);
  // One unit along world y: camera x.
  EXPECT_NEAR((p1.ToCamera(Eigen::Vector3d(0, 1, 5)) - Eigen::Vector3d(1, 0, 0)).norm(), 0, 1e-15);
}

TEST_F(TrajectoryLogTest, MalformedFramesNameFileAndLine) {
  struct Case {
    std::string content, where, what;
  };
  const Case cases[] = {
      {"0 0\n1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n", ":1:", "3 integers"},
      {"0 0 x\n", ":1:", "invalid integer"},
      {"0 0 0\n1 0 0 0\n0 1 0 0\n", ":3:", "truncated"},
      {"0 0 0\n1 0 0 0\n0 1 0\n0 0 1 0\n0 0 0 1\n", ":3:", "4 numbers"},
      {"0 0 0\n1 0 0 0\n0 1 0 0\n0 0 1 nan\n0 0 0 1\n", ":4:", "matrix entry"},
      {"0 0 0\n1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 1 1\n", ":5:", "0 0 0 1"},
      {"0 0 0\n2 0 0 0\n0 2 0 0\n0 0 2 0\n0 0 0 1\n", ":1:", "not a rotation"},
      {"0 0 0\n-1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n", ":1:", "not a rotation"},
  };
  for (const Case& c : cases) {
    const std::string path = Write("bad.log", c.content);
    try {
      ReadTrajectoryLog(path);
      ADD_FAILURE() << "accepted: " << c.content;
    } catch (const InputError& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find(path + c.where), std::string::npos) << m;
      EXPECT_NE(m.find(c.what), std::string::npos) << m;
    }
  }
}

TEST_F(TrajectoryLogTest, WriteReadRoundTripIsExact) {
  const std::vector<TrajectoryFrame> in = ReadTrajectoryLog(Write("a.log", kLog));
  std::vector<TrajectoryFrame> frames = in;
  frames.push_back(TrajectoryFrame::FromPose(Pose::FromQt(Eigen::Quaterniond(0.3, -0.5, 0.1, 0.8).normalized(),
                                                          Eigen::Vector3d(1.0 / 3.0, -2e5, 7.25)),
                                             {2, 2, 0}));
  WriteTrajectoryLog(frames, (dir_ / "b.log").string());
  const std::vector<TrajectoryFrame> out = ReadTrajectoryLog((dir_ / "b.log").string());
  ASSERT_EQ(out.size(), 3u);
  for (size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(out[i].header, frames[i].header);
    EXPECT_EQ(out[i].camera_to_world, frames[i].camera_to_world);
  }
  EXPECT_NEAR((out[2].ToPose().C() - frames[2].ToPose().C()).norm(), 0, 1e-9);
}

TEST_F(TrajectoryLogTest, ConvertsASceneIntoTheDatasetLayout) {
  Write("scene/000002.jpg", testing::JpegPhoto(1920, 1080, "b"));
  Write("scene/000001.jpg", testing::JpegPhoto(1920, 1080, "a"));
  Write("scene/notes.txt", "not a photo");
  const std::string cams = Write("cameras.txt", "1 PINHOLE 1920 1080 1100 1100 960 540\n");
  TanksAndTemplesInput in;
  in.log_path = Write("scene/Scene_COLMAP_SfM.log", kLog);
  in.images_dir = (dir_ / "scene").string();
  in.cameras_path = cams;
  const std::string out = (dir_ / "out").string();
  EXPECT_EQ(ConvertTanksAndTemples(in, out), 2u);
  const Reconstruction gt = ReadColmapText(out + "/gt", /*points_optional=*/true);
  ASSERT_EQ(gt.images.size(), 2u);
  // Frames follow the sorted names: the second frame is 000002.jpg.
  const Image& second = gt.images.at(*gt.FindImageByName("000002.jpg"));
  EXPECT_NEAR((second.pose.C() - Eigen::Vector3d(0, 0, 5)).norm(), 0, 1e-12);
  EXPECT_NEAR((gt.images.at(*gt.FindImageByName("000001.jpg")).pose.C() - Eigen::Vector3d(1, 2, 3)).norm(), 0, 1e-12);
  EXPECT_EQ(ReadColmapCameras(out + "/cameras.txt").at(1).params, (std::vector<double>{1100, 1100, 960, 540}));
  EXPECT_EQ(Read(dir_ / "out" / "images" / "000001.jpg"), testing::JpegPhoto(1920, 1080, "a"));  // a link to the original
  EXPECT_TRUE(std::filesystem::is_symlink(dir_ / "out" / "images" / "000001.jpg"));
  EXPECT_FALSE(std::filesystem::exists(dir_ / "out" / "images" / "notes.txt"));
  EXPECT_FALSE(std::filesystem::exists(dir_ / "out" / "camera_map.txt"));

  // A list in another order assigns the frames in that order; a count mismatch is an error.
  in.image_list = Write("list.txt", "# frame order\n000002.jpg\n000001.jpg\n");
  DatasetLayoutOptions copy;
  copy.copy_images = true;
  ConvertTanksAndTemples(in, out, copy);
  const Reconstruction gt2 = ReadColmapText(out + "/gt", true);
  EXPECT_NEAR((gt2.images.at(*gt2.FindImageByName("000002.jpg")).pose.C() - Eigen::Vector3d(1, 2, 3)).norm(), 0, 1e-12);
  EXPECT_FALSE(std::filesystem::is_symlink(dir_ / "out" / "images" / "000001.jpg"));
  EXPECT_EQ(Read(dir_ / "out" / "images" / "000001.jpg"), testing::JpegPhoto(1920, 1080, "a"));
  in.image_list = Write("list.txt", "000001.jpg\n");
  try {
    ConvertTanksAndTemples(in, out);
    ADD_FAILURE() << "count mismatch accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("2 frames but 1 images"), std::string::npos) << e.what();
  }
  in.image_list = Write("list.txt", "000001.jpg\nmissing.jpg\n");
  EXPECT_THROW(ConvertTanksAndTemples(in, out), InputError);
}

}  // namespace
}  // namespace pgba
