// Scenario-specific geometry: the orbit ring looks at its object, the long focal ring has a
// ~2 degree lens and a withheld loop whose correspondences reproject with the true poses,
// the aerial block has 80/60 overlap and scales to 2000 images, the video sees a plane.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <set>

#include "pgba/geometry/triangulation.h"
#include "tests/synthetic/synthetic_test_helpers.h"

namespace pgba {
namespace {
using namespace pgba::test;

TEST(SyntheticOrbit, RingOfCamerasLookingAtTheObject) {
  const SyntheticScene s = Generate(SyntheticScenario::kOrbit, 0.5, 0.0);
  ASSERT_EQ(s.gt.images.size(), 70u);
  const Camera& cam = s.gt.cameras.begin()->second;
  EXPECT_EQ(cam.width, 1920);
  EXPECT_EQ(cam.height, 1080);
  EXPECT_NEAR(cam.MeanFocal(), 1160, 10);
  // Object centre = centroid of the points; every camera looks within a few degrees of it.
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (const auto& [id, p] : s.gt.points3D) centre += p.xyz;
  centre /= s.gt.points3D.size();
  for (const auto& [id, im] : s.gt.images) {
    const Eigen::Vector3d to_centre = (centre - im.pose.C()).normalized();
    EXPECT_LT(std::acos(std::min(1.0, to_centre.dot(im.pose.ViewingDirection()))) * kRadToDeg, 10.0) << im.name;
  }
  // Consecutive images are neighbours on the ring, and the ring closes.
  const Eigen::Vector3d first = s.gt.images.at(1).pose.C(), last = s.gt.images.at(70).pose.C();
  EXPECT_LT((first - last).norm(), 2.0 * (s.gt.images.at(2).pose.C() - first).norm() + 0.5);
}

TEST(SyntheticLongFocal, TwoDegreeLensAndWithheldLoop) {
  const double noise = 0.5;
  const SyntheticScene s = Generate(SyntheticScenario::kLongFocal, noise, 0.05);
  const uint32_t n = s.gt.images.size();
  ASSERT_EQ(n, 93u);
  const Camera& cam = s.gt.cameras.begin()->second;
  const double fov_deg = 2.0 * std::atan(0.5 * cam.width / cam.MeanFocal()) * kRadToDeg;
  EXPECT_NEAR(fov_deg, 2.0, 0.3);
  // The loop is real: the ring's two ends are neighbours.
  const double step = (s.gt.images.at(2).pose.C() - s.gt.images.at(1).pose.C()).norm();
  EXPECT_LT((s.gt.images.at(1).pose.C() - s.gt.images.at(n).pose.C()).norm(), 3.0 * step);

  const auto first = [&](uint32_t id) { return id <= 3; };
  const auto last = [&](uint32_t id) { return id > n - 3; };
  for (const auto& [pid, p] : s.gt.points3D) {
    const bool has_first = std::any_of(p.track.begin(), p.track.end(), [&](auto& e) { return first(e.image_id); });
    const bool has_last = std::any_of(p.track.begin(), p.track.end(), [&](auto& e) { return last(e.image_id); });
    ASSERT_FALSE(has_first && has_last) << "track " << pid << " links the two ends of the loop";
  }

  ASSERT_GE(s.loop_pairs.size(), 100u);
  std::vector<double> residuals;
  std::set<std::pair<std::string, std::string>> linked;
  for (const auto& c : s.loop_pairs) {
    const auto i = s.gt.FindImageByName(c.name_i), j = s.gt.FindImageByName(c.name_j);
    ASSERT_TRUE(i && j);
    EXPECT_TRUE(first(*i) && last(*j)) << c.name_i << " " << c.name_j;
    linked.insert({c.name_i, c.name_j});
    const TriangulatedPoint t =
        TriangulateTrack({{s.gt.images.at(*i).pose, &cam, c.xy_i}, {s.gt.images.at(*j).pose, &cam, c.xy_j}});
    ASSERT_TRUE(t.ok);
    for (double r : t.residuals_px) residuals.push_back(r);
  }
  EXPECT_GE(linked.size(), 6u) << "the withheld correspondences should span several image pairs";
  double sum2 = 0;
  for (double r : residuals) sum2 += r * r;
  const double rms = std::sqrt(sum2 / residuals.size());
  std::cout << s.loop_pairs.size() << " loop pairs over " << linked.size() << " image pairs, two-view RMS " << rms
            << " px" << std::endl;
  // Two views, 4 measurements, 3 unknowns: E[sum r^2] = noise^2 per pair, so the RMS per
  // observation is noise / sqrt(2). Outliers never enter the loop pairs.
  EXPECT_NEAR(rms, noise / std::sqrt(2.0), 0.15 * noise);
}

TEST(SyntheticLongFocal, NoLoopForTinyRings) {
  EXPECT_FALSE(Generate(SyntheticScenario::kLongFocal, 0.5, 0.0, 1, 40).loop_pairs.empty());
  EXPECT_TRUE(Generate(SyntheticScenario::kLongFocal, 0.5, 0.0, 1, 3).loop_pairs.empty());
  EXPECT_TRUE(Generate(SyntheticScenario::kOrbit, 0.5, 0.0).loop_pairs.empty());
}

// Ground footprint of an image on z = 0 as an axis-aligned box (attitudes are near nadir).
Eigen::Vector4d Footprint(const Reconstruction& rec, const Image& im) {
  const Camera& cam = rec.CameraOf(im);
  Eigen::Vector4d box(INFINITY, INFINITY, -INFINITY, -INFINITY);
  for (double u : {0.0, double(cam.width)})
    for (double v : {0.0, double(cam.height)}) {
      const Eigen::Vector3d ray = im.pose.R().transpose() * cam.PixelToBearing({u, v});
      const Eigen::Vector3d g = im.pose.C() - ray * (im.pose.C().z() / ray.z());
      box.head<2>() = box.head<2>().cwiseMin(g.head<2>());
      box.tail<2>() = box.tail<2>().cwiseMax(g.head<2>());
    }
  return box;
}

double Overlap1D(double a0, double a1, double b0, double b1) {
  return std::max(0.0, std::min(a1, b1) - std::max(a0, b0)) / (a1 - a0);
}

TEST(SyntheticAerial, EightySixtyOverlapInSixStrips) {
  const SyntheticScene s = Generate(SyntheticScenario::kAerial, 0.5, 0.0);
  // Names stripSS_IIII.jpg: strips and their order.
  std::map<int, std::vector<const Image*>> strips;
  for (const auto& [id, im] : s.gt.images) strips[std::stoi(im.name.substr(5, 2))].push_back(&im);
  ASSERT_EQ(strips.size(), 6u);
  std::vector<double> along, across;
  for (auto& [k, images] : strips) {
    EXPECT_EQ(images.size(), 12u);
    std::sort(images.begin(), images.end(), [](auto a, auto b) { return a->name < b->name; });
    for (size_t i = 0; i + 1 < images.size(); ++i) {
      const Eigen::Vector4d a = Footprint(s.gt, *images[i]), b = Footprint(s.gt, *images[i + 1]);
      // The strips fly along x.
      along.push_back(Overlap1D(a[0], a[2], b[0], b[2]));
    }
    if (!strips.count(k + 1)) continue;
    for (const Image* im : images) {
      // Nearest image of the next strip along the flight line.
      const Image* best = nullptr;
      for (const Image* jm : strips[k + 1])
        if (!best || std::abs(jm->pose.C().x() - im->pose.C().x()) < std::abs(best->pose.C().x() - im->pose.C().x()))
          best = jm;
      const Eigen::Vector4d a = Footprint(s.gt, *im), b = Footprint(s.gt, *best);
      across.push_back(Overlap1D(a[1], a[3], b[1], b[3]));
    }
  }
  const auto mean = [](const std::vector<double>& v) { return std::accumulate(v.begin(), v.end(), 0.0) / v.size(); };
  std::cout << "aerial overlap along " << mean(along) << " across " << mean(across) << std::endl;
  EXPECT_NEAR(mean(along), 0.8, 0.02);
  EXPECT_NEAR(mean(across), 0.6, 0.02);
  // Single pairs vary with the attitude jitter (0.5 degree of pitch moves a footprint by 6 m).
  for (double o : along) EXPECT_NEAR(o, 0.8, 0.1);
  for (double o : across) EXPECT_NEAR(o, 0.6, 0.1);
  // Nadir: every optical axis within a few degrees of straight down.
  for (const auto& [id, im] : s.gt.images)
    EXPECT_GT(-im.pose.ViewingDirection().z(), std::cos(3.0 / kRadToDeg)) << im.name;
}

TEST(SyntheticAerial, ScalesToTwoThousandImages) {
  const SyntheticScene s = Generate(SyntheticScenario::kAerial, 0.5, 0.0, 1, 2000);
  ASSERT_EQ(s.gt.images.size(), 2000u);
  EXPECT_EQ(s.gt.CheckConsistency(), "");
  for (const auto& [id, im] : s.gt.images) ASSERT_GE(im.points2D.size(), 50u) << im.name;
  EXPECT_TRUE(ViewGraphConnected(s.gt));
  const double mean_track = double(s.gt.NumObservations()) / s.gt.points3D.size();
  EXPECT_GE(mean_track, 2.5);
  EXPECT_LE(mean_track, 8.0);
}

TEST(SyntheticPlanar, VideoAlongAWall) {
  const SyntheticScene s = Generate(SyntheticScenario::kPlanar, 0.5, 0.0);
  const Camera& cam = s.gt.cameras.begin()->second;
  EXPECT_EQ(cam.width, 739);
  EXPECT_EQ(cam.height, 458);
  EXPECT_NEAR(cam.MeanFocal(), 726, 5);
  // Every point lies on one plane: smallest singular value of the centred points ~ 0.
  Eigen::MatrixXd P(s.gt.points3D.size(), 3);
  int r = 0;
  for (const auto& [id, p] : s.gt.points3D) P.row(r++) = p.xyz.transpose();
  const Eigen::MatrixXd centred = P.rowwise() - P.colwise().mean();
  const Eigen::Vector3d sv = Eigen::JacobiSVD<Eigen::MatrixXd>(centred).singularValues();
  EXPECT_LT(sv[2], 1e-9 * sv[0]);
  // Highly overlapping: consecutive frames share many tracks.
  for (uint32_t id = 1; id < s.gt.images.size(); ++id) {
    std::set<int64_t> a, shared;
    for (const auto& o : s.gt.images.at(id).points2D) a.insert(o.point3D_id);
    for (const auto& o : s.gt.images.at(id + 1).points2D)
      if (a.count(o.point3D_id)) shared.insert(o.point3D_id);
    EXPECT_GE(shared.size(), 0.3 * a.size()) << "frames " << id << " and " << id + 1;
  }
}

}  // namespace
}  // namespace pgba
