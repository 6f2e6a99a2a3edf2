#include "averaging/global_init.h"
#include "averaging/outlier_injection.h"

#include <gtest/gtest.h>

#include "pgba/geometry/rotation.h"
#include "pgba/io/json_config.h"
#include "pgba/util/error.h"
#include "relative_motion_fixture.h"

namespace pgba {
namespace {

using test::Layout;

struct Accuracy {
  double rot_median, rot_max, centre_median, centre_max;
};

Accuracy Measure(const GlobalInitResult& r, const test::GroundTruth& gt) {
  std::map<uint32_t, Eigen::Matrix3d> R;
  std::map<uint32_t, Eigen::Vector3d> C;
  for (const auto& [id, p] : r.poses) {
    R[id] = p.R();
    C[id] = p.C();
  }
  const std::vector<double> rot = test::RotationErrorsDeg(R, gt.poses);
  const std::vector<double> centre = test::CentreErrorsRel(C, gt.poses, gt.extent, &R);
  return {test::Median(rot), test::Max(rot), test::Median(centre), test::Max(centre)};
}

class GlobalInitLayouts : public ::testing::TestWithParam<Layout> {};

// Pairs and triplets with 0.3 deg rotation/direction noise and 0.3% centre noise: every
// image registered, rotation error median < 0.1 deg and max < 0.5 deg, centre error median
// < 1% of the extent; each kept triplet's similarity maps the global poses onto its local
// poses (paper eq. 4) up to the noise.
TEST_P(GlobalInitLayouts, RegistersEverythingAccurately) {
  const Layout layout = GetParam();
  const test::GroundTruth gt = test::MakeLayout(layout, 21);
  const test::RelativeMotions m = test::MakeRelativeMotions(gt, test::NoiseModel(), 22);
  const GlobalInitResult r = RunGlobalInitialisation(test::MakeTracks(gt), m.pairs, m.triplets, GlobalInitOptions());
  ASSERT_TRUE(r.success) << r.message;
  EXPECT_EQ(r.poses.size(), gt.poses.size());
  EXPECT_TRUE(r.images_dropped.empty());
  EXPECT_EQ(r.triplets.size(), m.triplets.size());
  const Accuracy a = Measure(r, gt);
  std::cout << test::LayoutName(layout) << ": rotation error median " << a.rot_median << " max " << a.rot_max
            << " deg; centre error median " << a.centre_median << " max " << a.centre_max << " of extent; "
            << r.stats.seconds_total << " s\n";
  EXPECT_LT(a.rot_median, 0.1);
  EXPECT_LT(a.rot_max, 0.5);
  EXPECT_LT(a.centre_median, 0.01);
  for (const LocalMotion& t : r.triplets)
    for (int k = 0; k < 3; ++k) {
      const Pose predicted = t.global_to_local.Apply(r.poses.at(t.image_ids[k]));
      EXPECT_LT(RotationAngleDeg(predicted.R(), t.local_poses[k].R()), 1.0);
      const double size = (t.local_poses[0].C() - t.local_poses[1].C()).norm() +
                          (t.local_poses[1].C() - t.local_poses[2].C()).norm();
      EXPECT_LT((predicted.C() - t.local_poses[k].C()).norm(), 0.05 * size);
    }
}

INSTANTIATE_TEST_SUITE_P(All, GlobalInitLayouts, ::testing::Values(Layout::kOrbit, Layout::kAerial, Layout::kVideo));

class GlobalInitOutliers : public ::testing::TestWithParam<std::tuple<double, TripletCorruption>> {};

// 10% / 20% of the pairs' and triplets' rotations replaced by random ones (the sensitivity
// experiment's flag): median rotation error < 0.5 deg on the orbit and every image stays
// registered. Triplets corrupted as rotation measurements (the default) keep their local
// geometry: every triplet is kept and the corrupted relative rotations (two per triplet) are
// excluded as outlier edges. Triplets whose local poses are corrupted are identified and
// dropped.
TEST_P(GlobalInitOutliers, Orbit) {
  const auto [fraction, corruption] = GetParam();
  const test::GroundTruth gt = test::MakeLayout(Layout::kOrbit, 31);
  const test::RelativeMotions m = test::MakeRelativeMotions(gt, test::NoiseModel(), 32);
  OutlierInjectionOptions outliers;
  outliers.fraction = fraction;
  outliers.seed = 33;
  outliers.triplet_corruption = corruption;
  const CorruptedRelativeMotions c = CorruptRelativeMotions(outliers, m.pairs, m.triplets);
  const int triplets_corrupted = static_cast<int>(c.injected.triplets.size());
  const int pairs_corrupted = static_cast<int>(c.injected.pairs.size());
  EXPECT_EQ(triplets_corrupted, static_cast<int>(std::lround(fraction * m.triplets.size())));
  EXPECT_EQ(pairs_corrupted, static_cast<int>(std::lround(fraction * m.pairs.size())));
  // Corrupted as measurements only: the triplets handed to the initialisation keep their poses.
  if (corruption == TripletCorruption::kRelativeRotations) {
    for (size_t k = 0; k < m.triplets.size(); ++k)
      for (int v = 0; v < 3; ++v) ASSERT_EQ(c.triplets[k].local_poses[v].R(), m.triplets[k].local_poses[v].R());
  }
  const GlobalInitResult r =
      RunGlobalInitialisation(test::MakeTracks(gt), c.pairs, c.triplets, GlobalInitOptions(), &c.rotation_measurements);
  ASSERT_TRUE(r.success) << r.message;
  if (corruption == TripletCorruption::kLocalPoses) {
    EXPECT_GE(r.stats.triplets_rotation_outliers, triplets_corrupted * 9 / 10);
    EXPECT_LE(r.stats.triplets_rotation_outliers, triplets_corrupted + 2);
  } else {
    EXPECT_EQ(r.stats.triplets_rotation_outliers, 0);
    EXPECT_EQ(r.triplets.size(), m.triplets.size());
    EXPECT_GE(r.stats.rotation.num_outliers, 2 * triplets_corrupted);
    EXPECT_LE(r.stats.rotation.num_outliers, 2 * triplets_corrupted + pairs_corrupted);
    EXPECT_TRUE(r.stats.rotation.images_without_inliers.empty());
  }
  EXPECT_EQ(r.poses.size(), gt.poses.size());
  const Accuracy a = Measure(r, gt);
  std::cout << "orbit, " << fraction << " outliers: rotation error median " << a.rot_median << " max " << a.rot_max
            << " deg, centre median " << a.centre_median << "; " << r.stats.triplets_rotation_outliers
            << " triplets dropped of " << triplets_corrupted << " corrupted, "
            << r.stats.rotation.num_outliers << " relative rotations excluded\n";
  EXPECT_LT(a.rot_median, 0.5);
  EXPECT_LT(a.centre_median, 0.01);
}

INSTANTIATE_TEST_SUITE_P(All, GlobalInitOutliers,
                         ::testing::Combine(::testing::Values(0.1, 0.2),
                                            ::testing::Values(TripletCorruption::kRelativeRotations,
                                                              TripletCorruption::kLocalPoses)));

// With triplet filtering disabled (the sensitivity experiment hands outliers to the global
// BA), the triplets with corrupted local poses are kept.
TEST(GlobalInit, FilteringCanBeDisabled) {
  const test::GroundTruth gt = test::MakeLayout(Layout::kVideo, 5);
  const test::RelativeMotions m = test::MakeRelativeMotions(gt, test::NoiseModel(), 6);
  OutlierInjectionOptions outliers;
  outliers.fraction = 0.1;
  outliers.target = OutlierTarget::kTriplets;
  outliers.triplet_corruption = TripletCorruption::kLocalPoses;
  const CorruptedRelativeMotions c = CorruptRelativeMotions(outliers, m.pairs, m.triplets);
  EXPECT_TRUE(c.injected.pairs.empty());
  GlobalInitOptions options;
  options.max_triplet_rotation_error_deg = 0.0;
  options.max_triplet_centre_error = 0.0;
  const GlobalInitResult r =
      RunGlobalInitialisation(test::MakeTracks(gt), c.pairs, c.triplets, options, &c.rotation_measurements);
  ASSERT_TRUE(r.success);
  EXPECT_EQ(r.triplets.size(), m.triplets.size());
  EXPECT_LT(Measure(r, gt).rot_median, 0.5);
}

// A view graph that falls apart: the largest triplet component is reconstructed; images of a
// smaller component, images touched by a single triplet corner only, images with pairs but
// no triplet and images without any relative motion are dropped and named.
TEST(GlobalInit, LargestComponentAndDroppedImages) {
  const test::GroundTruth gt = test::MakeLayout(Layout::kOrbit, 41);
  test::RelativeMotions m = test::MakeRelativeMotions(gt, test::NoiseModel(), 42);
  Reconstruction tracks = test::MakeTracks(gt);
  auto add_image = [&](uint32_t id) {
    Image im;
    im.image_id = id;
    im.name = "extra_" + std::to_string(id) + ".jpg";
    im.camera_id = 1;
    tracks.images[id] = im;
  };
  // A separate small cluster 100, 101, 102, 103 (two triplets sharing a pair).
  for (uint32_t id = 100; id <= 103; ++id) add_image(id);
  LocalMotion t = m.triplets[0];
  t.image_ids = {100, 101, 102};
  m.triplets.push_back(t);
  t.image_ids = {101, 102, 103};
  m.triplets.push_back(t);
  // Image 200 attached to the main cluster by a triplet touching it in image 1 only.
  add_image(200);
  add_image(201);
  t.image_ids = {1, 200, 201};
  m.triplets.push_back(t);
  // Image 300: pairs only. Image 400: nothing.
  add_image(300);
  add_image(400);
  TwoViewGeometry p = m.pairs[0];
  p.image_id1 = 1;
  p.image_id2 = 300;
  m.pairs.push_back(p);

  const GlobalInitResult r = RunGlobalInitialisation(tracks, m.pairs, m.triplets, GlobalInitOptions());
  ASSERT_TRUE(r.success);
  EXPECT_EQ(r.poses.size(), gt.poses.size());
  EXPECT_EQ(r.dropped_image_ids, (std::vector<uint32_t>{100, 101, 102, 103, 200, 201, 300, 400}));
  EXPECT_EQ(r.images_dropped, (std::vector<std::string>{"extra_100.jpg", "extra_101.jpg", "extra_102.jpg",
                                                        "extra_103.jpg", "extra_200.jpg", "extra_201.jpg",
                                                        "extra_300.jpg", "extra_400.jpg"}));
  EXPECT_EQ(r.stats.triplets_outside_component, 3);
  const nlohmann::json report = GlobalInitReport(r);
  EXPECT_EQ(report["images_dropped"].size(), 8u);
  EXPECT_EQ(report["images_registered"], gt.poses.size());
  EXPECT_EQ(report["triplets_dropped"]["outside_component"], 3);
  EXPECT_TRUE(report.contains("seconds"));
  EXPECT_LT(Measure(r, gt).rot_median, 0.1);
}

// No triplets at all: nothing registered, every image named, no crash.
TEST(GlobalInit, NoTriplets) {
  const test::GroundTruth gt = test::MakeLayout(Layout::kOrbit, 1);
  const test::RelativeMotions m = test::MakeRelativeMotions(gt, test::NoiseModel(), 1);
  const GlobalInitResult r = RunGlobalInitialisation(test::MakeTracks(gt), m.pairs, {}, GlobalInitOptions());
  EXPECT_FALSE(r.success);
  EXPECT_TRUE(r.poses.empty());
  EXPECT_EQ(r.images_dropped.size(), gt.poses.size());
  const GlobalInitResult empty = RunGlobalInitialisation(Reconstruction(), {}, {}, GlobalInitOptions());
  EXPECT_FALSE(empty.success);
}

// Unusable relative motions are ignored and counted; pure garbage finishes without a crash.
TEST(GlobalInit, BadInputNeverCrashes) {
  const test::GroundTruth gt = test::MakeLayout(test::Layout::kVideo, 3);
  test::RelativeMotions m = test::MakeRelativeMotions(gt, test::NoiseModel(), 4);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  m.pairs[0].R_21(0, 0) = nan;
  m.pairs[1].t_21.setZero();
  m.pairs[2].image_id2 = m.pairs[2].image_id1;
  m.triplets[0].local_poses[1] = Pose::FromRC(Eigen::Matrix3d::Identity(), Eigen::Vector3d(nan, 0, 0));
  m.triplets[1].image_ids[2] = m.triplets[1].image_ids[0];
  for (Pose& p : m.triplets[2].local_poses) p = Pose::FromRC(p.R(), Eigen::Vector3d(1, 2, 3));
  const GlobalInitResult r = RunGlobalInitialisation(test::MakeTracks(gt), m.pairs, m.triplets, GlobalInitOptions());
  ASSERT_TRUE(r.success);
  EXPECT_EQ(r.stats.pairs_invalid, 3);
  EXPECT_EQ(r.stats.triplets_invalid, 3);
  EXPECT_EQ(r.poses.size(), gt.poses.size());
  EXPECT_LT(Measure(r, gt).rot_median, 0.1);

  // Every rotation and every local centre random.
  std::mt19937_64 rng(5);
  std::normal_distribution<double> n(0.0, 1.0);
  for (TwoViewGeometry& p : m.pairs) p.R_21 = RandomRotation(rng);
  for (LocalMotion& t : m.triplets)
    for (Pose& p : t.local_poses) p = Pose::FromRC(RandomRotation(rng), Eigen::Vector3d(n(rng), n(rng), n(rng)));
  const GlobalInitResult g = RunGlobalInitialisation(test::MakeTracks(gt), m.pairs, m.triplets, GlobalInitOptions());
  EXPECT_EQ(g.poses.size() + g.images_dropped.size(), gt.poses.size());
}

TEST(GlobalInit, UnknownImageIdIsInputError) {
  const test::GroundTruth gt = test::MakeLayout(Layout::kOrbit, 1);
  test::RelativeMotions m = test::MakeRelativeMotions(gt, test::NoiseModel(), 1);
  m.pairs[3].image_id2 = 999;
  EXPECT_THROW(RunGlobalInitialisation(test::MakeTracks(gt), m.pairs, m.triplets, GlobalInitOptions()), InputError);
}

TEST(GlobalInit, Deterministic) {
  const test::GroundTruth gt = test::MakeLayout(Layout::kAerial, 2);
  const test::RelativeMotions m = test::MakeRelativeMotions(gt, test::NoiseModel(), 3);
  OutlierInjectionOptions outliers;
  outliers.fraction = 0.1;
  const CorruptedRelativeMotions c = CorruptRelativeMotions(outliers, m.pairs, m.triplets);
  const CorruptedRelativeMotions d = CorruptRelativeMotions(outliers, m.pairs, m.triplets);
  EXPECT_EQ(c.injected.pairs, d.injected.pairs);
  EXPECT_EQ(c.injected.triplets, d.injected.triplets);
  const GlobalInitResult a =
      RunGlobalInitialisation(test::MakeTracks(gt), c.pairs, c.triplets, GlobalInitOptions(), &c.rotation_measurements);
  const GlobalInitResult b =
      RunGlobalInitialisation(test::MakeTracks(gt), d.pairs, d.triplets, GlobalInitOptions(), &d.rotation_measurements);
  ASSERT_EQ(a.poses.size(), b.poses.size());
  for (const auto& [id, p] : a.poses) {
    EXPECT_EQ(p.q().coeffs(), b.poses.at(id).q().coeffs());
    EXPECT_EQ(p.t(), b.poses.at(id).t());
  }
  ASSERT_EQ(a.triplets.size(), b.triplets.size());
  for (size_t t = 0; t < a.triplets.size(); ++t) EXPECT_EQ(a.triplets[t].global_to_local.Matrix(), b.triplets[t].global_to_local.Matrix());
}

// Options are JSON-loadable with defaults for absent fields; bad values are InputErrors.
TEST(GlobalInit, OptionsFromJson) {
  const nlohmann::json j = nlohmann::json::parse(R"({"rotation": {"loss": "l_half", "loss_scale_deg": 3},
      "translation": {"refine": false}})");
  const GlobalInitOptions o = j.get<GlobalInitOptions>();
  EXPECT_EQ(o.rotation.loss.type, LossType::kLHalf);
  EXPECT_EQ(o.rotation.loss.scale, 3.0);
  EXPECT_EQ(o.rotation.max_irls_iterations, RotationAveragingOptions().max_irls_iterations);
  EXPECT_FALSE(o.translation.refine);
  EXPECT_EQ(nlohmann::json(o).get<GlobalInitOptions>().rotation.loss.type, LossType::kLHalf);
  // Every LossType is an IRLS loss (optim/loss_function_options.h); a name none has is refused.
  EXPECT_EQ(nlohmann::json::parse(R"({"rotation": {"loss": "cauchy"}})").get<GlobalInitOptions>().rotation.loss.type,
            LossType::kCauchy);
  EXPECT_THROW(nlohmann::json::parse(R"({"rotation": {"loss": "tukey"}})").get<GlobalInitOptions>(),
               nlohmann::json::exception);
  // The sensitivity experiment's options (not a config section: set by the commands).
  const OutlierInjectionOptions out =
      nlohmann::json::parse(R"({"fraction": 0.2, "target": "pairs"})").get<OutlierInjectionOptions>();
  EXPECT_EQ(out.target, OutlierTarget::kPairs);
  EXPECT_EQ(out.triplet_corruption, TripletCorruption::kRelativeRotations);
  EXPECT_THROW(nlohmann::json::parse(R"({"target": "all"})").get<OutlierInjectionOptions>(), nlohmann::json::exception);
  EXPECT_EQ(nlohmann::json::parse(R"({"triplet_corruption": "local_poses"})").get<OutlierInjectionOptions>().triplet_corruption,
            TripletCorruption::kLocalPoses);
  EXPECT_THROW(nlohmann::json::parse(R"({"triplet_corruption": "poses"})").get<OutlierInjectionOptions>(),
               nlohmann::json::exception);
  // Through the config reader: InputError naming the file.
  GlobalInitOptions read;
  ReadSection(Config::Parse(R"({"averaging": {"rotation": {"loss_scale_deg": 2.5}}})", "cfg.json"), "averaging",
              &read);
  EXPECT_EQ(read.rotation.loss.scale, 2.5);
  EXPECT_EQ(read.rotation.loss.type, LossType::kGemanMcClure);
  try {
    ReadSection(Config::Parse(R"({"averaging": {"rotation": {"loss": "tukey"}}})", "cfg.json"), "averaging", &read);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("cfg.json"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("tukey"), std::string::npos) << e.what();
  }
  EXPECT_THROW(ReadSection(Config::Parse(R"({"averaging": {"rotation": {"los": "l1"}}})", "cfg.json"), "averaging",
                           &read),
               InputError);
  GlobalInitOptions bad;
  bad.rotation.loss.scale = -1;
  EXPECT_THROW(RunGlobalInitialisation(Reconstruction(), {}, {}, bad), InputError);
}

// The l1/2 loss of Chatterjee & Govindu is an alternative default: also accurate.
TEST(GlobalInit, LHalfLoss) {
  const test::GroundTruth gt = test::MakeLayout(Layout::kOrbit, 8);
  const test::RelativeMotions m = test::MakeRelativeMotions(gt, test::NoiseModel(), 9);
  GlobalInitOptions options;
  options.rotation.loss.type = LossType::kLHalf;
  OutlierInjectionOptions outliers;
  outliers.fraction = 0.2;
  const CorruptedRelativeMotions c = CorruptRelativeMotions(outliers, m.pairs, m.triplets);
  const GlobalInitResult r =
      RunGlobalInitialisation(test::MakeTracks(gt), c.pairs, c.triplets, options, &c.rotation_measurements);
  ASSERT_TRUE(r.success);
  const Accuracy a = Measure(r, gt);
  std::cout << "l1/2, 20% outliers: rotation error median " << a.rot_median << " max " << a.rot_max << "\n";
  EXPECT_LT(a.rot_median, 0.5);
}

}  // namespace
}  // namespace pgba
