// ETH3D scenes: a hand-made scene in ETH3D's layout (undistorted DSLR calibration as a COLMAP
// text model, image names under dslr_images_undistorted/) becomes images/ cameras.txt gt/
// with identical poses; fisheye (distorted) calibrations and broken scenes are clear errors.
#include "pgba/io/eth3d.h"

#include <Eigen/Geometry>

#include "pgba/io/eth3d_slam.h"

#include <gtest/gtest.h>

#include "pgba/io/colmap_text.h"
#include "pgba/util/error.h"
#include "tests/io/dataset_test_dir.h"

namespace pgba {
namespace {

class Eth3dTest : public testing::TempDirTest {
 protected:
  // Two PINHOLE cameras (ETH3D's undistorted images may differ in size), three images.
  void MakeScene(const std::string& cameras) {
    Write("scene/dslr_calibration_undistorted/cameras.txt", cameras);
    Write("scene/dslr_calibration_undistorted/images.txt",
          "# Image list with two lines of data per image:\n"
          "1 0.7 0.1 -0.5 0.5 1.5 -0.25 3 1 dslr_images_undistorted/DSC_0001.JPG\n"
          "100 200 7 300 400 -1\n"
          "2 1 0 0 0 0 0 0 1 dslr_images_undistorted/DSC_0002.JPG\n"
          "110 210 7\n"
          "5 0.5 0.5 0.5 0.5 -4 2 1 2 dslr_images_undistorted/DSC_0007.JPG\n"
          "\n");
    Write("scene/dslr_calibration_undistorted/points3D.txt", "7 1 2 3 255 0 0 0.5 1 0 2 0\n");
    for (const char* n : {"DSC_0001.JPG", "DSC_0002.JPG"})
      Write(std::string("scene/images/dslr_images_undistorted/") + n, testing::JpegPhoto(6048, 4032, n));
    Write("scene/images/dslr_images_undistorted/DSC_0007.JPG", testing::JpegPhoto(4032, 6048, "DSC_0007.JPG"));
  }
  const std::string kCameras =
      "# Camera list\n1 PINHOLE 6048 4032 3410.5 3409.2 3020.1 2012.3\n2 SIMPLE_PINHOLE 4032 6048 3400 2016 3024\n";
};

TEST_F(Eth3dTest, ConvertsPosesExactlyWithPlainNames) {
  MakeScene(kCameras);
  const std::string scene = (dir_ / "scene").string(), out = (dir_ / "out").string();
  const Reconstruction original = ReadColmapText(scene + "/dslr_calibration_undistorted");
  EXPECT_EQ(ConvertEth3dScene(scene, out), 3u);

  const Reconstruction gt = ReadColmapText(out + "/gt", /*points_optional=*/true);
  ASSERT_EQ(gt.images.size(), 3u);
  EXPECT_TRUE(gt.points3D.empty());  // ETH3D's points are COLMAP's, not ground truth
  for (const auto& [id, im] : original.images) {
    const Image& g = gt.images.at(id);
    EXPECT_EQ("dslr_images_undistorted/" + g.name, im.name);
    EXPECT_EQ(g.camera_id, im.camera_id);
    EXPECT_LT((g.pose.q().coeffs() - im.pose.q().coeffs()).norm(), 1e-15);
    EXPECT_LT((g.pose.t() - im.pose.t()).norm(), 1e-15);
    EXPECT_TRUE(g.points2D.empty());
    EXPECT_EQ(Read(dir_ / "out" / "images" / g.name).substr(17), g.name);  // the photo, linked
  }
  const std::map<uint32_t, Camera> cams = ReadColmapCameras(out + "/cameras.txt");
  ASSERT_EQ(cams.size(), 2u);
  EXPECT_EQ(cams.at(2).model, CameraModel::kSimplePinhole);
  EXPECT_EQ(cams.at(1).params, (std::vector<double>{3410.5, 3409.2, 3020.1, 2012.3}));
  // Several cameras: the map `pgba run --camera-map` needs.
  EXPECT_EQ(Read(dir_ / "out" / "camera_map.txt"),
            "# IMAGE_NAME CAMERA_ID\nDSC_0001.JPG 1\nDSC_0002.JPG 1\nDSC_0007.JPG 2\n");
}

TEST_F(Eth3dTest, RejectsTheDistortedFisheyeCalibration) {
  MakeScene("1 THIN_PRISM_FISHEYE 6048 4032 3411 3410 3021 2012 -0.28 0.07 0 0 0 0 0 0 0 0\n");
  const std::string path = (dir_ / "scene/dslr_calibration_undistorted/cameras.txt").string();
  try {
    ConvertEth3dScene((dir_ / "scene").string(), (dir_ / "out").string());
    ADD_FAILURE() << "fisheye accepted";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(path + ":1:"), std::string::npos) << m;
    EXPECT_NE(m.find("THIN_PRISM_FISHEYE"), std::string::npos) << m;
    EXPECT_NE(m.find("undistorted"), std::string::npos) << m;
  }
  EXPECT_FALSE(std::filesystem::exists(dir_ / "out" / "gt"));
}

TEST_F(Eth3dTest, MissingPhotoOrCalibrationIsAnInputError) {
  MakeScene(kCameras);
  std::filesystem::remove(dir_ / "scene/images/dslr_images_undistorted/DSC_0007.JPG");
  try {
    ConvertEth3dScene((dir_ / "scene").string(), (dir_ / "out").string());
    ADD_FAILURE() << "missing photo accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("DSC_0007.JPG"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(std::filesystem::exists(dir_ / "out" / "gt"));
  EXPECT_THROW(ConvertEth3dScene((dir_ / "nowhere").string(), (dir_ / "out").string()), InputError);
}

// ETH3D SLAM (TUM format): camera-to-world ground truth paired with frames by timestamp.
class Eth3dSlamTest : public testing::TempDirTest {
 protected:
  // A PNG header (signature + IHDR) of the given size: all the converter reads.
  void WritePng(const std::string& rel, int w, int h) {
    std::string b = std::string("\x89PNG\r\n\x1a\n", 8) + std::string("\0\0\0\x0dIHDR", 8);
    for (int v : {w, h})
      for (int shift : {24, 16, 8, 0}) b.push_back(static_cast<char>((v >> shift) & 0xff));
    Write(rel, b + std::string(5, '\0'));
  }
};

TEST_F(Eth3dSlamTest, PairsFramesWithGroundTruthByTimestamp) {
  WritePng("seq/rgb/100.000000.png", 739, 458);
  WritePng("seq/rgb/100.033333.png", 739, 458);
  WritePng("seq/rgb/100.066666.png", 739, 458);
  Write("seq/calibration.txt", "726.28 726.28 354.65 186.47\n");
  Write("seq/rgb.txt",
        "# timestamp filename\n100.000000 rgb/100.000000.png\n100.033333 rgb/100.033333.png\n"
        "100.066666 rgb/100.066666.png\n");
  // Frame 2: camera z axis (optical axis) = world x: q_wc = 90 degrees about world y.
  const double c = std::sqrt(0.5);
  Write("seq/groundtruth.txt",
        "# timestamp tx ty tz qx qy qz qw\n100.000001 1 2 3 0 0 0 1\n100.033334 4 5 6 0 " + std::to_string(c) + " 0 " +
            std::to_string(c) + "\n");  // the third frame has none
  const std::string out = (dir_ / "out").string();
  EXPECT_EQ(ConvertEth3dSlamSequence((dir_ / "seq").string(), out), 2u);
  const Reconstruction gt = ReadColmapText(out + "/gt", true);
  ASSERT_EQ(gt.images.size(), 2u);
  const Camera& cam = gt.cameras.at(1);
  EXPECT_EQ(cam.width, 739);
  EXPECT_EQ(cam.height, 458);
  EXPECT_EQ(cam.params, (std::vector<double>{726.28, 726.28, 354.65, 186.47}));
  const Pose& p0 = gt.images.at(*gt.FindImageByName("100.000000.png")).pose;
  const Pose& p1 = gt.images.at(*gt.FindImageByName("100.033333.png")).pose;
  EXPECT_LT((p0.C() - Eigen::Vector3d(1, 2, 3)).norm(), 1e-12);
  EXPECT_LT((p1.C() - Eigen::Vector3d(4, 5, 6)).norm(), 1e-12);
  // A point one unit ahead along world x is on the optical axis of frame 2.
  EXPECT_LT((p1.ToCamera(Eigen::Vector3d(5, 5, 6)) - Eigen::Vector3d(0, 0, 1)).norm(), 1e-5);
  EXPECT_EQ(Read(dir_ / "out" / "images" / "100.000000.png").substr(1, 3), "PNG");

  Write("seq/groundtruth.txt", "100.0 1 2 3 0 0 0\n");
  try {
    ConvertEth3dSlamSequence((dir_ / "seq").string(), out);
    ADD_FAILURE() << "short line accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("groundtruth.txt:1:"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace pgba
