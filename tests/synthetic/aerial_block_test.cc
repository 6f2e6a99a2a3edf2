// The rendered aerial block (modules/synthetic/aerial_block.h) and the footprint truth
// (ground_footprint.h): footprints against their closed form, the flight plan's overlaps
// against the options, rendered pixels against the true projection (the same ground point
// looks the same in two overlapping photos), determinism, and bad options.
#include "modules/synthetic/aerial_block.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <opencv2/imgproc.hpp>
#include <random>

#include "modules/synthetic/ground_footprint.h"
#include "pgba/util/error.h"
#include "tests/apps/cli_runner.h"

namespace pgba {
namespace {
namespace fs = std::filesystem;

AerialBlockOptions Small() {
  AerialBlockOptions o = DefaultAerialBlockOptions();
  o.image.num_images = 24;
  o.image.width = 320;
  o.image.height = 240;
  o.ground_sample_m = 0.3;
  o.strips = 3;
  return o;
}

TEST(GroundFootprint, NadirRectangleAndConvexIntersection) {
  Camera cam;
  cam.model = CameraModel::kPinhole;
  cam.width = 400;
  cam.height = 300;
  cam.params = {500, 500, 200, 150};
  Eigen::Matrix3d down;  // looks along -z
  down << 1, 0, 0, 0, -1, 0, 0, 0, -1;
  const synthetic::GroundPolygon fp = synthetic::GroundFootprint(cam, Pose::FromRC(down, {10, 20, 100}), 0.0);
  ASSERT_EQ(fp.size(), 4u);
  EXPECT_NEAR(synthetic::PolygonArea(fp), 80.0 * 60.0, 1e-6);  // 400 px x 100 m / 500 px = 80 m
  for (const Eigen::Vector2d& c : fp) {
    EXPECT_NEAR(std::abs(c.x() - 10), 40.0, 1e-9);
    EXPECT_NEAR(std::abs(c.y() - 20), 30.0, 1e-9);
  }
  // Shifted by 20 m along x: 60 x 60 in common, over the smaller (equal) area.
  const synthetic::GroundPolygon fq = synthetic::GroundFootprint(cam, Pose::FromRC(down, {30, 20, 100}), 0.0);
  EXPECT_NEAR(synthetic::FootprintOverlap(fp, fq), 0.75, 1e-9);
  EXPECT_EQ(synthetic::FootprintOverlap(fp, synthetic::GroundFootprint(cam, Pose::FromRC(down, {200, 20, 100}), 0.0)),
            0.0);
  // The square [-1, 1]^2 and the diamond |x| + |y| <= sqrt(2): the square without the four
  // corner triangles of legs 2 - sqrt(2).
  const synthetic::GroundPolygon sq = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
  const double r = std::sqrt(2.0);
  const synthetic::GroundPolygon diamond = {{r, 0}, {0, r}, {-r, 0}, {0, -r}};
  EXPECT_NEAR(synthetic::PolygonArea(synthetic::IntersectConvex(sq, diamond)), 4.0 - 2.0 * (2.0 - r) * (2.0 - r),
              1e-12);
}

TEST(AerialBlock, FlightPlanHasTheRequestedOverlapsAndRendersTheTrueGeometry) {
  const AerialBlockOptions o = Small();
  const AerialBlock block = MakeAerialBlock(o);
  ASSERT_EQ(block.gt.images.size(), 24u);
  EXPECT_EQ(block.strips, 3);
  EXPECT_NEAR(block.altitude, 0.8 * 320 * 0.3, 1e-9);
  // Neighbours along a strip overlap by ~forward_overlap, the same position on the next
  // strip by ~side_overlap; attitude and position jitter move both by a few percent (a 2
  // degree tilt shifts the footprint by 3.5% of its length), which on average lowers the
  // forward overlap (measured medians: 0.717 forward, 0.525 side).
  std::vector<double> forward, side;
  for (int s = 0; s < 3; ++s)
    for (int i = 0; i + 1 < 8; ++i)
      forward.push_back(synthetic::FootprintOverlap(block.footprints[8 * s + i], block.footprints[8 * s + i + 1]));
  for (int i = 0; i < 8; ++i)  // strip 1 flies back: its image 7 - i is above strip 0's image i
    side.push_back(synthetic::FootprintOverlap(block.footprints[i], block.footprints[8 + 7 - i]));
  std::sort(forward.begin(), forward.end());
  std::sort(side.begin(), side.end());
  std::cout << "overlap median forward " << forward[forward.size() / 2] << ", side " << side[side.size() / 2]
            << std::endl;
  EXPECT_NEAR(forward[forward.size() / 2], 0.73, 0.03);
  EXPECT_NEAR(side[side.size() / 2], 0.5, 0.05);

  // A ground point looks the same in two overlapping photos: 9 x 9 patches around its true
  // projections correlate (NCC), except the few points a building hides in one of them. A
  // pose convention mixed up (a transposed rotation, a flipped image axis) would decorrelate
  // them.
  std::vector<cv::Mat> gray(2);
  const size_t a = 3, b = 4;  // consecutive on strip 0
  for (int t = 0; t < 2; ++t) cv::cvtColor(RenderAerialImage(block, o, t ? b : a), gray[t], cv::COLOR_BGR2GRAY);
  const Camera& cam = block.gt.cameras.at(1);
  std::mt19937_64 rng(5);
  const Eigen::Vector4d box(block.footprints[a][0].x(), block.footprints[a][0].y(), block.footprints[a][2].x(),
                            block.footprints[a][2].y());
  std::vector<double> ncc;
  for (int trial = 0; trial < 400 && ncc.size() < 100; ++trial) {
    std::uniform_real_distribution<double> ux(std::min(box[0], box[2]), std::max(box[0], box[2]));
    std::uniform_real_distribution<double> uy(std::min(box[1], box[3]), std::max(box[1], box[3]));
    const Eigen::Vector3d X(ux(rng), uy(rng), 0.0);
    cv::Mat patch[2];
    bool inside = true;
    for (int t = 0; t < 2 && inside; ++t) {
      const Image& im = block.gt.images.at(static_cast<uint32_t>((t ? b : a) + 1));
      const Eigen::Vector2d p = cam.Project(im.pose.ToCamera(X));
      inside = p.x() > 8 && p.y() > 8 && p.x() < cam.width - 8 && p.y() < cam.height - 8;
      if (inside) cv::getRectSubPix(gray[t], cv::Size(9, 9), cv::Point2f(p.x() - 0.5f, p.y() - 0.5f), patch[t], CV_32F);
    }
    if (!inside) continue;
    cv::Mat score;
    cv::matchTemplate(patch[0], patch[1], score, cv::TM_CCOEFF_NORMED);
    ncc.push_back(score.at<float>(0, 0));
  }
  ASSERT_GE(ncc.size(), 60u);
  std::sort(ncc.begin(), ncc.end());
  std::cout << ncc.size() << " ground points, patch NCC quartiles " << ncc[ncc.size() / 4] << " " << ncc[ncc.size() / 2]
            << " " << ncc[3 * ncc.size() / 4] << std::endl;
  // Measured: quartiles 0.935, 0.981, 0.990 (noise and resampling keep them below 1).
  EXPECT_GT(ncc[ncc.size() / 2], 0.96);
  EXPECT_GT(ncc[ncc.size() / 4], 0.9);

  // Every pixel shows texture (the ground covers every footprint) and a render repeats.
  const cv::Mat img = RenderAerialImage(block, o, 10);
  cv::Mat g;
  cv::cvtColor(img, g, cv::COLOR_BGR2GRAY);
  EXPECT_LT(cv::countNonZero(g < 3), 5);
  EXPECT_EQ(cv::norm(img, RenderAerialImage(block, o, 10), cv::NORM_INF), 0.0);
}

TEST(AerialBlock, SameImagesOnOneThreadAsOnTwo) {
  const AerialBlockOptions o = Small();
  cv::Mat one, two;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one = RenderAerialImage(MakeAerialBlock(o), o, 17);
  }
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 2);
    two = RenderAerialImage(MakeAerialBlock(o), o, 17);
  }
  EXPECT_EQ(cv::norm(one, two, cv::NORM_INF), 0.0);
}

TEST(AerialBlock, WritesTheDatasetLayoutAndRejectsBadOptions) {
  const fs::path out = fs::temp_directory_path() / ("pgba_aerial_" + std::to_string(::getpid()));
  fs::remove_all(out);
  const test::CliResult r = test::RunPgba(
      "synth --render --scene aerial --images 8 --strips 2 --width 160 --height 120 "
      "--ground-sample 0.5 --out " +
      out.string());
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(std::distance(fs::directory_iterator(out / "images"), fs::directory_iterator()), 8);
  EXPECT_TRUE(fs::exists(out / "cameras.txt"));
  EXPECT_TRUE(fs::exists(out / "gt" / "images.txt"));
  std::ifstream overlap(out / "overlap.txt");
  std::string n1, n2;
  double v = 0;
  ASSERT_TRUE(overlap >> n1 >> n2 >> v);
  EXPECT_EQ(n1, "strip00_0000.png");
  EXPECT_EQ(n2, "strip00_0001.png");
  EXPECT_NEAR(v, 0.75, 0.05);

  const std::vector<std::pair<std::string, std::string>> cases = {
      {"--scene aerial --forward-overlap 0.95", "--forward-overlap"},
      {"--scene aerial --side-overlap 0.1", "--side-overlap"},
      {"--scene aerial --ground-sample 0", "--ground-sample"},
      {"--scene aerial --strips 0", "--strips"},
      {"--scene aerial --images 3", "--images"},
      {"--scene street", "--scene"},
      {"--forward-overlap 0.7", "--forward-overlap"},
      {"--strips 3", "--strips"}};
  for (const auto& [args, name] : cases) {
    const test::CliResult bad = test::RunPgba("synth --render " + args + " --out " + (out / "bad").string());
    EXPECT_EQ(bad.code, 2) << args << ": " << bad.output;
    EXPECT_NE(bad.output.find(name), std::string::npos) << args << ": " << bad.output;
  }
  EXPECT_FALSE(fs::exists(out / "bad" / "images"));
  fs::remove_all(out);
}

}  // namespace
}  // namespace pgba
