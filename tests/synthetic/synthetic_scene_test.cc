// Properties every synthetic scenario shares, checked against its own ground truth:
// observations reproject to the noise level, outliers are what was asked, the input model is
// the gt model with unknown poses, tracks are limited like matched features, every image is
// observed and connected, and generation is deterministic.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <set>

#include "pgba/util/error.h"
#include "tests/synthetic/synthetic_test_helpers.h"

namespace pgba {
namespace {
using namespace pgba::test;

// Images in which a point projects inside the frame and in front of the camera: an upper
// bound of the views that could see it (ignores occlusion and surface orientation).
int InFrameViews(const Reconstruction& rec, const Eigen::Vector3d& X) {
  int n = 0;
  for (const auto& [id, im] : rec.images) {
    const Eigen::Vector3d xc = im.pose.ToCamera(X);
    if (xc.z() <= 0) continue;
    const Camera& cam = rec.CameraOf(im);
    const Eigen::Vector2d px = cam.Project(xc);
    n += px.x() >= 0 && px.y() >= 0 && px.x() <= cam.width && px.y() <= cam.height;
  }
  return n;
}

struct Stats {
  double inlier_rms = 0, inlier_max = 0;
  size_t observations = 0, large_errors = 0;
};

Stats ObservationStats(const SyntheticScene& s) {
  std::set<std::pair<uint32_t, uint32_t>> outliers;
  for (const auto& e : s.outliers) outliers.insert({e.image_id, e.point2D_idx});
  Stats st;
  double sum2 = 0;
  size_t inliers = 0;
  for (const auto& [id, im] : s.gt.images)
    for (uint32_t k = 0; k < im.points2D.size(); ++k) {
      const double err = ReprojectionError(s.gt, im, im.points2D[k]);
      ++st.observations;
      st.large_errors += err > 4.0;
      if (outliers.count({id, k})) continue;
      sum2 += err * err;
      st.inlier_max = std::max(st.inlier_max, err);
      ++inliers;
    }
  st.inlier_rms = std::sqrt(sum2 / inliers);
  return st;
}

void ExpectIdentical(const Reconstruction& a, const Reconstruction& b, bool same_geometry) {
  ASSERT_EQ(a.cameras.size(), b.cameras.size());
  for (const auto& [id, c] : a.cameras) {
    const Camera& d = b.cameras.at(id);
    EXPECT_EQ(c.model, d.model);
    EXPECT_EQ(c.width, d.width);
    EXPECT_EQ(c.height, d.height);
    EXPECT_EQ(c.params, d.params);
  }
  ASSERT_EQ(a.images.size(), b.images.size());
  for (const auto& [id, im] : a.images) {
    const Image& jm = b.images.at(id);
    EXPECT_EQ(im.name, jm.name);
    EXPECT_EQ(im.camera_id, jm.camera_id);
    if (same_geometry) {
      EXPECT_EQ(im.pose.q().coeffs(), jm.pose.q().coeffs());
      EXPECT_EQ(im.pose.t(), jm.pose.t());
    }
    ASSERT_EQ(im.points2D.size(), jm.points2D.size());
    for (size_t k = 0; k < im.points2D.size(); ++k) {
      EXPECT_EQ(im.points2D[k].xy, jm.points2D[k].xy);
      EXPECT_EQ(im.points2D[k].point3D_id, jm.points2D[k].point3D_id);
    }
  }
  ASSERT_EQ(a.points3D.size(), b.points3D.size());
  for (const auto& [id, p] : a.points3D) {
    const Point3D& q = b.points3D.at(id);
    if (same_geometry) {
      EXPECT_EQ(p.xyz, q.xyz);
    }
    ASSERT_EQ(p.track.size(), q.track.size());
    for (size_t k = 0; k < p.track.size(); ++k) {
      EXPECT_EQ(p.track[k].image_id, q.track[k].image_id);
      EXPECT_EQ(p.track[k].point2D_idx, q.track[k].point2D_idx);
    }
  }
}

class EveryScenario : public ::testing::TestWithParam<SyntheticScenario> {};

TEST_P(EveryScenario, ObservationsMatchGroundTruthNoiseAndOutliers) {
  const double noise = 0.5, fraction = 0.1;
  const SyntheticScene s = Generate(GetParam(), noise, fraction);
  ASSERT_EQ(s.gt.CheckConsistency(), "");
  const Stats st = ObservationStats(s);
  std::cout << SyntheticScenarioName(GetParam()) << ": " << s.gt.images.size() << " images, " << s.gt.points3D.size()
            << " points, " << st.observations << " observations, inlier RMS " << st.inlier_rms << " px, max "
            << st.inlier_max << " px, " << s.outliers.size() << " outliers, " << st.large_errors << " errors > 4 px"
            << std::endl;
  // 2D error of N(0, noise^2 I2): E|e|^2 = 2 noise^2.
  EXPECT_NEAR(st.inlier_rms, noise * std::sqrt(2.0), 0.03 * noise * std::sqrt(2.0));
  EXPECT_LT(st.inlier_max, 8.0 * noise);
  const double expected = std::round(fraction * st.observations);
  EXPECT_EQ(double(s.outliers.size()), expected);
  // Independently of the outlier list: the observations far from their true projection.
  EXPECT_NEAR(double(st.large_errors) / st.observations, fraction, 0.002);
  for (const auto& e : s.outliers) {
    const Image& im = s.gt.images.at(e.image_id);
    const Eigen::Vector2d& xy = im.points2D.at(e.point2D_idx).xy;
    const Camera& cam = s.gt.CameraOf(im);
    EXPECT_TRUE(xy.x() >= 0 && xy.y() >= 0 && xy.x() <= cam.width && xy.y() <= cam.height);
  }
}

TEST_P(EveryScenario, NoiselessObservationsAreExactProjections) {
  const SyntheticScene s = Generate(GetParam(), 0.0, 0.0);
  EXPECT_TRUE(s.outliers.empty());
  EXPECT_LT(ObservationStats(s).inlier_max, 1e-6);
}

TEST_P(EveryScenario, InputIsGroundTruthWithUnknownPoses) {
  const SyntheticScene s = Generate(GetParam(), 0.5, 0.05);
  ASSERT_EQ(s.input.CheckConsistency(), "");
  ExpectIdentical(s.gt, s.input, /*same_geometry=*/false);
  for (const auto& [id, im] : s.input.images) {
    EXPECT_EQ(im.pose.q().coeffs(), Eigen::Quaterniond::Identity().coeffs());
    EXPECT_EQ(im.pose.t(), Eigen::Vector3d::Zero());
  }
  for (const auto& [id, p] : s.input.points3D) EXPECT_EQ(p.xyz, Eigen::Vector3d::Zero());
}

TEST_P(EveryScenario, TracksAreLimitedLikeMatchedFeatures) {
  const SyntheticScene s = Generate(GetParam(), 0.5, 0.0);
  std::vector<double> lengths;
  size_t complete = 0;
  double in_frame_sum = 0;
  for (const auto& [id, p] : s.gt.points3D) {
    ASSERT_GE(p.track.size(), 2u);
    std::set<uint32_t> views;
    for (const auto& e : p.track) views.insert(e.image_id);
    ASSERT_EQ(views.size(), p.track.size()) << "a track sees an image twice";
    lengths.push_back(p.track.size());
    const int in_frame = InFrameViews(s.gt, p.xyz);
    in_frame_sum += in_frame;
    complete += static_cast<int>(p.track.size()) >= in_frame;
  }
  const double mean = std::accumulate(lengths.begin(), lengths.end(), 0.0) / lengths.size();
  const double max = *std::max_element(lengths.begin(), lengths.end());
  const double in_frame_mean = in_frame_sum / lengths.size();
  std::cout << SyntheticScenarioName(GetParam()) << ": mean track " << mean << ", max " << max
            << ", mean in-frame views " << in_frame_mean << ", complete tracks " << double(complete) / lengths.size()
            << std::endl;
  EXPECT_GE(mean, 2.5);
  EXPECT_LE(mean, 8.0);
  EXPECT_GE(max, 2.0 * mean) << "no long tracks";
  EXPECT_LT(max, 0.5 * s.gt.images.size());
  EXPECT_LT(mean, 0.6 * in_frame_mean) << "tracks hold nearly every view that could see the point";
  EXPECT_LT(double(complete) / lengths.size(), 0.25);
}

TEST_P(EveryScenario, EveryImageObservedAndViewGraphConnected) {
  const SyntheticScene s = Generate(GetParam(), 0.5, 0.0);
  for (const auto& [id, im] : s.gt.images) EXPECT_GE(im.points2D.size(), 100u) << im.name;
  EXPECT_TRUE(ViewGraphConnected(s.gt));
  EXPECT_GT(s.extent, 0.0);
}

TEST_P(EveryScenario, DeterministicForASeed) {
  const SyntheticScene a = Generate(GetParam(), 0.5, 0.1, 7);
  const SyntheticScene b = Generate(GetParam(), 0.5, 0.1, 7);
  ExpectIdentical(a.gt, b.gt, true);
  ASSERT_EQ(a.loop_pairs.size(), b.loop_pairs.size());
  for (size_t k = 0; k < a.loop_pairs.size(); ++k) {
    EXPECT_EQ(a.loop_pairs[k].name_i, b.loop_pairs[k].name_i);
    EXPECT_EQ(a.loop_pairs[k].xy_i, b.loop_pairs[k].xy_i);
    EXPECT_EQ(a.loop_pairs[k].xy_j, b.loop_pairs[k].xy_j);
  }
  const SyntheticScene c = Generate(GetParam(), 0.5, 0.1, 8);
  ASSERT_EQ(a.gt.images.size(), c.gt.images.size());
  EXPECT_NE(a.gt.images.at(1).pose.C(), c.gt.images.at(1).pose.C());
  EXPECT_NE(a.gt.NumObservations(), c.gt.NumObservations());
}

TEST_P(EveryScenario, HonoursImageCount) {
  const SyntheticScene s = Generate(GetParam(), 0.5, 0.0, 3, 24);
  EXPECT_EQ(s.gt.images.size(), 24u);
  EXPECT_EQ(s.gt.CheckConsistency(), "");
  EXPECT_TRUE(ViewGraphConnected(s.gt));
}

INSTANTIATE_TEST_SUITE_P(Synthetic, EveryScenario,
                         ::testing::Values(SyntheticScenario::kOrbit, SyntheticScenario::kLongFocal,
                                           SyntheticScenario::kAerial, SyntheticScenario::kPlanar),
                         [](const auto& info) { return std::string(SyntheticScenarioName(info.param)); });

TEST(SyntheticOptionsTest, BadOptionsAreInputErrors) {
  const auto bad = [](auto edit) {
    SyntheticOptions o;
    edit(o);
    EXPECT_THROW(GenerateSyntheticScene(o), InputError);
  };
  bad([](SyntheticOptions& o) { o.noise_px = -0.1; });
  bad([](SyntheticOptions& o) { o.noise_px = NAN; });
  bad([](SyntheticOptions& o) { o.outlier_fraction = 1.0; });
  bad([](SyntheticOptions& o) { o.outlier_fraction = -0.01; });
  bad([](SyntheticOptions& o) { o.num_images = 2; });
  bad([](SyntheticOptions& o) { o.num_images = -5; });
  bad([](SyntheticOptions& o) { o.num_points = -1; });
  bad([](SyntheticOptions& o) { o.scenario = static_cast<SyntheticScenario>(17); });
  SyntheticScenario sc;
  EXPECT_FALSE(ParseSyntheticScenario("temple", &sc));
  for (const char* name : {"orbit", "longfocal", "aerial", "planar"}) {
    ASSERT_TRUE(ParseSyntheticScenario(name, &sc));
    EXPECT_STREQ(SyntheticScenarioName(sc), name);
  }
}

TEST(SyntheticOptionsTest, JsonRoundTrip) {
  SyntheticOptions o;
  o.scenario = SyntheticScenario::kAerial;
  o.seed = 42;
  o.noise_px = 0.25;
  o.num_images = 500;
  const nlohmann::json j = o;
  EXPECT_EQ(j.at("scenario"), "aerial");
  const SyntheticOptions back = j.get<SyntheticOptions>();
  EXPECT_EQ(back.scenario, o.scenario);
  EXPECT_EQ(back.seed, 42u);
  EXPECT_EQ(back.noise_px, 0.25);
  EXPECT_EQ(back.num_images, 500);
  // Missing keys keep their documented defaults.
  const SyntheticOptions partial = nlohmann::json::parse(R"({"scenario": "planar"})").get<SyntheticOptions>();
  EXPECT_EQ(partial.scenario, SyntheticScenario::kPlanar);
  EXPECT_EQ(partial.noise_px, SyntheticOptions().noise_px);
}

}  // namespace
}  // namespace pgba
