// Rendered synthetic scenes: the renderer draws a world point where the camera model
// projects it (to a few hundredths of a pixel), the z-buffer keeps the nearest surface,
// rendering is deterministic per seed, and the written layout is that of shared/datasets.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "modules/synthetic/lens_remap.h"
#include "modules/synthetic/procedural_texture.h"
#include "modules/synthetic/quad_renderer.h"
#include "modules/synthetic/rendered_scene.h"
#include "modules/synthetic/synthetic_layout.h"
#include "modules/synthetic/synthetic_lens.h"
#include "pgba/io/colmap_text.h"
#include "pgba/util/error.h"

namespace pgba {
namespace {
namespace fs = std::filesystem;
using synthetic::TexturedQuad;

Camera TestCamera(int w, int h, double f, double cx, double cy) {
  Camera c;
  c.camera_id = 1;
  c.model = CameraModel::kPinhole;
  c.width = w;
  c.height = h;
  c.params = {f, 1.05 * f, cx, cy};
  return c;
}

// Intensity-weighted centroid (COLMAP pixel convention) of the green channel in a window.
Eigen::Vector2d Centroid(const cv::Mat& img, const Eigen::Vector2d& around, int radius) {
  double sw = 0, sx = 0, sy = 0;
  const int cx = static_cast<int>(around.x()), cy = static_cast<int>(around.y());
  for (int y = cy - radius; y <= cy + radius; ++y)
    for (int x = cx - radius; x <= cx + radius; ++x) {
      if (x < 0 || y < 0 || x >= img.cols || y >= img.rows) continue;
      const double w = img.at<cv::Vec3b>(y, x)[1];
      sw += w;
      sx += w * (x + 0.5);
      sy += w * (y + 0.5);
    }
  return {sx / sw, sy / sw};
}

TEST(QuadRenderer, DrawsWorldPointsWhereTheCameraProjectsThem) {
  // A slanted 0.6 x 0.5 m plate 2 m in front of a camera with an off-centre principal point,
  // black with Gaussian spots centred on known texels.
  const Camera cam = TestCamera(320, 240, 400.0, 151.3, 127.8);
  const Eigen::Matrix3d R = synthetic::LookAtRotation(Eigen::Vector3d(0.3, -2.0, 0.2), Eigen::Vector3d(0, 0, 0),
                                                      Eigen::Vector3d::UnitZ());
  const Pose pose = Pose::FromRC(R, Eigen::Vector3d(0.3, -2.0, 0.2));
  TexturedQuad q;
  q.origin = Eigen::Vector3d(-0.3, 0.1, -0.25);
  q.u_axis = Eigen::Vector3d(0.6, 0.15, 0.0);
  q.v_axis = Eigen::Vector3d(0.0, -0.1, 0.5);
  q.texture = cv::Mat(250, 300, CV_8UC3, cv::Scalar::all(0));
  const std::vector<cv::Point> spots = {{40, 30}, {150, 125}, {260, 210}, {75, 200}};
  for (const cv::Point& s : spots)
    for (int dy = -6; dy <= 6; ++dy)
      for (int dx = -6; dx <= 6; ++dx)
        q.texture.at<cv::Vec3b>(s.y + dy, s.x + dx) =
            cv::Vec3b::all(static_cast<uchar>(std::lround(250.0 * std::exp(-(dx * dx + dy * dy) / 8.0))));

  // Every spot's centroid in `img` is where `camera` projects the spot's texel centre.
  double max_shift = 0.0;  // of the lens camera's projections from the pinhole's
  const auto check_spots = [&](const cv::Mat& img, const Camera& camera, const std::string& what) {
    ASSERT_EQ(img.cols, 320);
    ASSERT_EQ(img.rows, 240);
    for (const cv::Point& s : spots) {
      const Eigen::Vector3d X = q.origin + (s.x + 0.5) / 300.0 * q.u_axis + (s.y + 0.5) / 250.0 * q.v_axis;
      const Eigen::Vector2d expected = camera.Project(pose.ToCamera(X));
      const Eigen::Vector2d got = Centroid(img, expected, 5);
      EXPECT_LT((got - expected).norm(), 0.05) << what << " spot " << s << ": got " << got.transpose()
                                                << " expected " << expected.transpose();
      max_shift = std::max(max_shift, (cam.Project(pose.ToCamera(X)) - expected).norm());
    }
  };
  for (int ss : {1, 2, 3})
    check_spots(synthetic::RenderQuads({q}, cam, pose, ss), cam, "supersampling " + std::to_string(ss));
  // Through a strong pincushion lens (k1 = 0.8, so that the spots near the centre move by
  // pixels; OPENCV for the two focals): the spots land where the distorted camera projects
  // them, 0.9 px (20x the tolerance) from where the pinhole would.
  const Camera lens_cam = synthetic::WithRadialDistortion(cam, 0.8, "k1");
  for (int ss : {1, 2})
    check_spots(synthetic::LensRenderer(lens_cam, ss).Render({q}, pose), lens_cam,
                "lens, supersampling " + std::to_string(ss));
  EXPECT_GT(max_shift, 0.5) << "the lens hardly distorts the spots: the test would not see a pinhole render";
}

TEST(QuadRenderer, NearestSurfaceWinsWhateverTheOrderAndBehindIsInvisible) {
  const Camera cam = TestCamera(64, 48, 60.0, 32.0, 24.0);
  const Pose pose = Pose::FromRC(Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero());  // looks along +z
  const auto plate = [](double z, cv::Scalar colour) {
    TexturedQuad q;
    q.origin = Eigen::Vector3d(-5 * z, -5 * z, z);
    q.u_axis = Eigen::Vector3d(10 * z, 0, 0);
    q.v_axis = Eigen::Vector3d(0, 10 * z, 0);
    q.texture = cv::Mat(8, 8, CV_8UC3, colour);
    return q;
  };
  const TexturedQuad near = plate(1.0, {0, 0, 200}), far = plate(3.0, {0, 200, 0}), behind = plate(-0.5, {200, 0, 0});
  for (const auto& order : {std::vector<TexturedQuad>{near, far, behind}, std::vector<TexturedQuad>{behind, far, near}}) {
    const cv::Mat img = synthetic::RenderQuads(order, cam, pose, 2);
    EXPECT_EQ(img.at<cv::Vec3b>(24, 32), cv::Vec3b(0, 0, 200));
    EXPECT_EQ(img.at<cv::Vec3b>(0, 0), cv::Vec3b(0, 0, 200));
  }
  // A wall crossing the camera plane (x = 1, from z = -5 to z = 5) covers the right part of
  // the image only; nothing of its part behind the camera leaks into the left part.
  TexturedQuad wall;
  wall.origin = Eigen::Vector3d(1, -5, -5);
  wall.u_axis = Eigen::Vector3d(0, 0, 10);
  wall.v_axis = Eigen::Vector3d(0, 10, 0);
  wall.texture = cv::Mat(16, 16, CV_8UC3, cv::Scalar(0, 0, 200));
  const cv::Mat img = synthetic::RenderQuads({wall}, cam, pose, 1);
  EXPECT_EQ(img.at<cv::Vec3b>(24, 60), cv::Vec3b(0, 0, 200));
  EXPECT_EQ(img.at<cv::Vec3b>(24, 4), cv::Vec3b(0, 0, 0));
}

TEST(ProceduralTexture, DeterministicNonRepetitiveAndTextured) {
  const cv::Mat a = synthetic::MakeProceduralTexture(300, 200, 7);
  const cv::Mat b = synthetic::MakeProceduralTexture(300, 200, 7);
  const cv::Mat c = synthetic::MakeProceduralTexture(300, 200, 8);
  ASSERT_EQ(a.type(), CV_8UC3);
  EXPECT_EQ(cv::norm(a, b, cv::NORM_INF), 0.0);
  EXPECT_GT(cv::norm(a, c, cv::NORM_L1) / a.total(), 10.0);
  // Contrast everywhere: every 25 x 25 tile has structure.
  cv::Mat gray;
  cv::cvtColor(a, gray, cv::COLOR_BGR2GRAY);
  for (int y = 0; y + 25 <= 200; y += 25)
    for (int x = 0; x + 25 <= 300; x += 25) {
      cv::Scalar mean, sd;
      cv::meanStdDev(gray(cv::Rect(x, y, 25, 25)), mean, sd);
      EXPECT_GT(sd[0], 4.0) << "flat tile at " << x << "," << y;
    }
  // Not periodic: a tile correlates poorly with the same tile shifted by any of a few
  // candidate periods.
  cv::Mat f;
  gray.convertTo(f, CV_32F);
  const cv::Mat tile = f(cv::Rect(100, 50, 64, 64));
  cv::Mat score;
  cv::matchTemplate(f, tile, score, cv::TM_CCOEFF_NORMED);
  int close = 0;
  for (int y = 0; y < score.rows; ++y)
    for (int x = 0; x < score.cols; ++x)
      if ((std::abs(x - 100) > 8 || std::abs(y - 50) > 8) && score.at<float>(y, x) > 0.8f) ++close;
  EXPECT_EQ(close, 0);
}

TEST(RenderedScene, DeterministicPerSeedWithConsistentGroundTruth) {
  RenderedSceneOptions o;
  o.num_images = 5;
  o.width = 160;
  o.height = 120;
  const RenderedScene a = RenderRoomScene(o);
  const RenderedScene b = RenderRoomScene(o);
  o.seed = 2;
  const RenderedScene c = RenderRoomScene(o);
  ASSERT_EQ(a.images.size(), 5u);
  ASSERT_EQ(a.gt.images.size(), 5u);
  for (size_t k = 0; k < 5; ++k) {
    EXPECT_EQ(cv::norm(a.images[k], b.images[k], cv::NORM_INF), 0.0) << k;
    EXPECT_GT(cv::norm(a.images[k], c.images[k], cv::NORM_L1), 0.0) << k;
    EXPECT_EQ(a.images[k].size(), cv::Size(160, 120));
    EXPECT_EQ(a.loop[k], a.gt.images.at(k + 1).name);
    // No black (uncovered) pixels: the room encloses every camera.
    cv::Mat gray;
    cv::cvtColor(a.images[k], gray, cv::COLOR_BGR2GRAY);
    EXPECT_LT(cv::countNonZero(gray < 3), 10) << k;
  }
  EXPECT_EQ(a.gt.cameras.at(1).params, (std::vector<double>{128.0, 128.0, 80.0, 60.0}));
  EXPECT_EQ(a.gt.CheckConsistency(), "");
  // The ring: consecutive views 72 degrees apart on average, all looking at the boxes.
  for (const auto& [id, im] : a.gt.images) {
    const Eigen::Vector3d C = im.pose.C();
    EXPECT_NEAR(C.head<2>().norm(), 2.4, 0.4);
    const Eigen::Vector3d axis = im.pose.R().row(2).transpose();  // optical axis, world frame
    EXPECT_GT(axis.dot((Eigen::Vector3d(0, 0, 0.7) - C).normalized()), 0.99);
  }
  EXPECT_THROW(
      {
        RenderedSceneOptions bad;
        bad.num_images = 2;
        RenderRoomScene(bad);
      },
      InputError);
}

TEST(RenderedScene, WritesTheDatasetLayout) {
  const fs::path dir = fs::temp_directory_path() / ("pgba_rendered_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  RenderedSceneOptions o;
  o.num_images = 4;
  o.width = 96;
  o.height = 64;
  const RenderedScene scene = RenderRoomScene(o);
  fs::create_directories(dir / "images");
  std::ofstream(dir / "images" / "stale.png") << "from an earlier run";
  WriteRenderedScene(scene, dir.string());
  EXPECT_FALSE(fs::exists(dir / "images" / "stale.png"));
  const Reconstruction gt = ReadColmapText((dir / "gt").string());
  EXPECT_TRUE(gt.points3D.empty());
  ASSERT_EQ(gt.images.size(), 4u);
  const auto cams = ReadColmapCameras((dir / "cameras.txt").string());
  ASSERT_EQ(cams.size(), 1u);
  EXPECT_EQ(cams.at(1).model, CameraModel::kPinhole);
  std::ifstream loop(dir / "loop.txt");
  std::string name;
  for (uint32_t id = 1; id <= 4; ++id) {
    ASSERT_TRUE(std::getline(loop, name));
    EXPECT_EQ(name, gt.images.at(id).name);
    EXPECT_NEAR((gt.images.at(id).pose.C() - scene.gt.images.at(id).pose.C()).norm(), 0.0, 1e-12);
    const cv::Mat img = cv::imread((dir / "images" / name).string(), cv::IMREAD_UNCHANGED);
    ASSERT_FALSE(img.empty()) << name;
    EXPECT_EQ(cv::norm(img, scene.images[id - 1], cv::NORM_INF), 0.0);  // PNG is lossless
  }
  EXPECT_FALSE(std::getline(loop, name));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace pgba
