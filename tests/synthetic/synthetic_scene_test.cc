// Synthetic scenes against their own ground truth: observations reproject to the noise
// level, outliers are what was asked, the input model is the gt model with unknown poses,
// tracks are limited like matched features, and each scenario has its geometry (ring looking
// inwards, ~2 degree lens with a withheld loop, 80/60 aerial overlap, planar wall).
#include "modules/synthetic/synthetic_scene.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <set>

#include "pgba/geometry/triangulation.h"
#include "pgba/util/error.h"

namespace pgba {
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;

double ReprojectionError(const Reconstruction& rec, const Image& im, const Point2D& obs) {
  const Point3D& p = rec.points3D.at(static_cast<uint64_t>(obs.point3D_id));
  return (rec.CameraOf(im).Project(im.pose.ToCamera(p.xyz)) - obs.xy).norm();
}

// Union-find over images linked by a common track.
bool ViewGraphConnected(const Reconstruction& rec) {
  std::map<uint32_t, uint32_t> parent;
  for (const auto& [id, im] : rec.images) parent[id] = id;
  std::function<uint32_t(uint32_t)> find = [&](uint32_t x) { return parent[x] == x ? x : parent[x] = find(parent[x]); };
  for (const auto& [pid, p] : rec.points3D)
    for (const auto& e : p.track) parent[find(e.image_id)] = find(p.track.front().image_id);
  std::set<uint32_t> roots;
  for (const auto& [id, im] : rec.images) roots.insert(find(id));
  return roots.size() == 1;
}

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

SyntheticScene Generate(SyntheticScenario scenario, double noise, double outliers, uint64_t seed = 1, int images = 0) {
  SyntheticOptions o;
  o.scenario = scenario;
  o.noise_px = noise;
  o.outlier_fraction = outliers;
  o.seed = seed;
  o.num_images = images;
  return GenerateSyntheticScene(o);
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
  double azimuth_span = 0;
  for (const auto& [id, im] : s.gt.images) {
    const Eigen::Vector3d to_centre = (centre - im.pose.C()).normalized();
    EXPECT_LT(std::acos(std::min(1.0, to_centre.dot(im.pose.ViewingDirection()))) * kRadToDeg, 10.0) << im.name;
    azimuth_span += 1;
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
