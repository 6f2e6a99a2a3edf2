// Whole-track motions (whole_track_motions.h): every track in exactly one motion with all of
// its views, and the consequence the method rests on: the sum of the motions' local Hessians
// is the point-based reduced camera system, checked against the Schur complement of one
// motion holding every image and every track (the point-based BA's own system).
#include "modules/local_hessian/whole_track_motions.h"

#include <gtest/gtest.h>

#include <map>
#include <random>
#include <set>

#include "modules/local_hessian/local_hessian.h"
#include "modules/mapper/pose_refinement.h"
#include "pgba/optim/intrinsics.h"
#include "tests/global_ba/global_ba_fixture.h"
#include "tests/local_hessian/ring_scene.h"

namespace pgba {
namespace {

using testing::MakeRingScene;
using testing::PosesOf;
using testing::RingSceneOptions;

Reconstruction Ring(int num_images, double visibility_deg, uint64_t seed) {
  RingSceneOptions o;
  o.num_images = num_images;
  o.num_points = 1500;
  o.visibility_deg = visibility_deg;
  o.noise_px = 0.5;
  o.seed = seed;
  return MakeRingScene(o);
}

// A 16-view ring through a SIMPLE_RADIAL lens (k -0.08): the self-calibration tests' scene.
RingSceneOptions LensRingOptions() {
  RingSceneOptions ro;
  ro.num_images = 16;
  ro.num_points = 1500;
  ro.visibility_deg = 60.0;
  ro.k1 = -0.08;
  ro.seed = 5;
  return ro;
}

std::set<uint32_t> PosedViews(const Point3D& p, const std::map<uint32_t, Pose>& poses) {
  std::set<uint32_t> v;
  for (const TrackElement& el : p.track)
    if (poses.count(el.image_id)) v.insert(el.image_id);
  return v;
}

TEST(WholeTrackMotions, EveryTrackInExactlyOneMotionWithAllItsViews) {
  const Reconstruction rec = Ring(24, 70.0, 3);
  std::map<uint32_t, Pose> poses = PosesOf(rec);
  poses.erase(poses.begin());  // an image without a pose: its observations must not count
  WholeTrackMotionOptions o;
  o.max_views = 8;
  o.min_tracks = 30;
  const std::vector<LocalMotion> motions = SelectWholeTrackMotions(rec, poses, o);
  ASSERT_GT(motions.size(), 1u);
  std::map<uint64_t, int> owner;
  for (size_t m = 0; m < motions.size(); ++m) {
    const std::set<uint32_t> views(motions[m].image_ids.begin(), motions[m].image_ids.end());
    EXPECT_EQ(views.size(), motions[m].image_ids.size());
    EXPECT_TRUE(std::is_sorted(motions[m].image_ids.begin(), motions[m].image_ids.end()));
    EXPECT_GE(static_cast<int>(motions[m].track_ids.size()), o.min_tracks);
    ASSERT_EQ(motions[m].local_poses.size(), motions[m].image_ids.size());
    for (const uint64_t t : motions[m].track_ids) {
      EXPECT_TRUE(owner.emplace(t, static_cast<int>(m)).second) << "track " << t << " in two motions";
      for (const uint32_t v : PosedViews(rec.points3D.at(t), poses)) EXPECT_TRUE(views.count(v)) << "track " << t;
    }
  }
  size_t expected = 0;
  for (const auto& [id, p] : rec.points3D) expected += PosedViews(p, poses).size() >= 2;
  EXPECT_EQ(owner.size(), expected);
  // Deterministic.
  const std::vector<LocalMotion> again = SelectWholeTrackMotions(rec, poses, o);
  ASSERT_EQ(again.size(), motions.size());
  for (size_t m = 0; m < motions.size(); ++m) {
    EXPECT_EQ(again[m].image_ids, motions[m].image_ids);
    EXPECT_EQ(again[m].track_ids, motions[m].track_ids);
  }
}

std::vector<LocalMotion> MotionsOfSix(const Reconstruction& rec, const std::map<uint32_t, Pose>& poses) {
  WholeTrackMotionOptions o;
  o.max_views = 6;
  return SelectWholeTrackMotions(rec, poses, o);
}

// One motion holding every image and every track: its h is the point-based BA's system.
LocalMotion WholeBlock(const Reconstruction& rec, const std::map<uint32_t, Pose>& poses) {
  LocalMotion all;
  for (const auto& [id, pose] : poses) {
    all.image_ids.push_back(id);
    all.local_poses.push_back(pose);
  }
  for (const auto& [id, p] : rec.points3D) all.track_ids.push_back(id);
  return all;
}

// The sum of the local Hessians (without their gauge priors: h_points) of the whole-track
// motions, all in the global frame at the same poses, equals the reduced camera system of
// the whole block, to rounding. With triplets it does not (tracks cut, observations counted
// several times): the difference the method removes.
TEST(WholeTrackMotions, SumOfLocalHessiansIsThePointBasedReducedCameraSystem) {
  const Reconstruction rec = Ring(16, 60.0, 5);
  const std::map<uint32_t, Pose> poses = PosesOf(rec);
  const LocalHessianOptions lh = LocalHessianOptions();
  const std::vector<LocalMotion> motions = MotionsOfSix(rec, poses);
  ASSERT_GT(motions.size(), 2u);
  const LocalMotion all = WholeBlock(rec, poses);
  const LocalHessian whole = ComputeLocalHessian(rec, all, 0, lh);
  ASSERT_EQ(whole.status, LocalHessianStatus::kOk);
  const Eigen::MatrixXd reference = whole.h.Dense() - whole.Prior();

  std::map<uint32_t, int> slot;
  for (size_t k = 0; k < all.image_ids.size(); ++k) slot[all.image_ids[k]] = static_cast<int>(k);
  Eigen::MatrixXd sum = Eigen::MatrixXd::Zero(reference.rows(), reference.cols());
  int points = 0;
  for (size_t m = 0; m < motions.size(); ++m) {
    const LocalHessian h = ComputeLocalHessian(rec, motions[m], static_cast<int>(m), lh);
    ASSERT_EQ(h.status, LocalHessianStatus::kOk) << m;
    points += h.num_points;
    const Eigen::MatrixXd hp = h.h.Dense() - h.Prior();
    for (int a = 0; a < h.num_views(); ++a)
      for (int b = 0; b < h.num_views(); ++b)
        sum.block<6, 6>(6 * slot.at(h.image_ids[a]), 6 * slot.at(h.image_ids[b])) += hp.block<6, 6>(6 * a, 6 * b);
  }
  EXPECT_EQ(points, whole.num_points);
  EXPECT_LE((sum - reference).norm(), 1e-9 * reference.norm());
}

// The same with self-calibration (paper, "Self-calibrating bundle adjustment"): the focal and
// the radial coefficient of the shared camera as unknowns of every h (6N + 2 rows). The
// motions' intrinsic rows add up, like their pose rows, to the point-based system's.
TEST(WholeTrackMotions, SumOfLocalHessiansWithIntrinsicsIsThePointBasedReducedCameraSystem) {
  const RingSceneOptions ro = LensRingOptions();
  const Reconstruction rec = MakeRingScene(ro);
  const std::map<uint32_t, Pose> poses = PosesOf(rec);
  const LocalHessianOptions lh = LocalHessianOptions();
  const FreeIntrinsics free = SelectFreeIntrinsics(rec.cameras, IntrinsicsOptions());
  ASSERT_EQ(free.at(1), (std::vector<int>{0, 3}));  // SIMPLE_RADIAL: f and k
  const std::vector<LocalMotion> motions = MotionsOfSix(rec, poses);
  ASSERT_GT(motions.size(), 2u);
  const LocalMotion all = WholeBlock(rec, poses);
  const LocalHessian whole = ComputeLocalHessian(rec, all, 0, lh, nullptr, &free);
  ASSERT_EQ(whole.status, LocalHessianStatus::kOk);
  const int n = 6 * whole.num_views();
  ASSERT_EQ(whole.h.rows(), n + 2);
  ASSERT_EQ(whole.intrinsics0.size(), 2);
  EXPECT_DOUBLE_EQ(whole.intrinsics0(0), ro.focal_px);
  EXPECT_DOUBLE_EQ(whole.intrinsics0(1), ro.k1);
  const Eigen::MatrixXd reference = whole.h.Dense() - whole.Prior();
  EXPECT_GT(reference.bottomRightCorner(2, 2).diagonal().minCoeff(), 0.0);

  std::map<uint32_t, int> slot;
  for (size_t k = 0; k < all.image_ids.size(); ++k) slot[all.image_ids[k]] = static_cast<int>(k);
  // Row of each unknown of motion h in the whole system: its views' pose rows, then the 2.
  Eigen::MatrixXd sum = Eigen::MatrixXd::Zero(reference.rows(), reference.cols());
  for (size_t m = 0; m < motions.size(); ++m) {
    const LocalHessian h = ComputeLocalHessian(rec, motions[m], static_cast<int>(m), lh, nullptr, &free);
    ASSERT_EQ(h.status, LocalHessianStatus::kOk) << m;
    ASSERT_EQ(h.num_intrinsics(), 2);
    std::vector<int> row;
    for (int a = 0; a < h.num_views(); ++a)
      for (int c = 0; c < 6; ++c) row.push_back(6 * slot.at(h.image_ids[a]) + c);
    row.push_back(n);
    row.push_back(n + 1);
    const Eigen::MatrixXd hp = h.h.Dense() - h.Prior();
    for (int a = 0; a < hp.rows(); ++a)
      for (int b = 0; b < hp.cols(); ++b) sum(row[a], row[b]) += hp(a, b);
  }
  EXPECT_LE((sum - reference).norm(), 1e-9 * reference.norm());
  // The intrinsic rows alone (their entries are far smaller than the poses' in these units).
  EXPECT_LE((sum - reference).bottomRows(2).norm(), 1e-9 * reference.bottomRows(2).norm());
}

// Away from the optimum (poses perturbed, the focal 2% long, k 0 against the lens's -0.08):
// the motions' reduced gradients g (paper eq. 3), pose rows and intrinsic rows, add up to the
// point-based reduced gradient, as their h do. This is what makes the re-linearised global BA
// Gauss-Newton on the point-based cost when it self-calibrates.
TEST(WholeTrackMotions, SumOfReducedGradientsWithIntrinsicsAwayFromTheOptimum) {
  const RingSceneOptions ro = LensRingOptions();
  Reconstruction rec = MakeRingScene(ro);
  rec.cameras.at(1).params[0] *= 1.02;
  rec.cameras.at(1).params[3] = 0.0;
  std::map<uint32_t, Pose> poses = PosesOf(rec);
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 1.0);
  for (auto& [id, pose] : poses) {
    const Eigen::Vector3d w(noise(rng), noise(rng), noise(rng));
    const Eigen::Vector3d c(noise(rng), noise(rng), noise(rng));
    pose = Pose::FromRC(pose.R() * Eigen::AngleAxisd(2e-3, w.normalized()).toRotationMatrix(), pose.C() + 0.01 * c);
  }
  const LocalHessianOptions lh = LocalHessianOptions();
  const FreeIntrinsics free = SelectFreeIntrinsics(rec.cameras, IntrinsicsOptions());
  const std::vector<LocalMotion> motions = MotionsOfSix(rec, poses);
  ASSERT_GT(motions.size(), 2u);
  const LocalMotion all = WholeBlock(rec, poses);
  const LocalHessian whole = ComputeLocalHessian(rec, all, 0, lh, nullptr, &free);
  ASSERT_EQ(whole.status, LocalHessianStatus::kOk);
  const int n = 6 * whole.num_views();
  const Eigen::VectorXd& reference = whole.reduced_gradient;
  ASSERT_EQ(reference.size(), n + 2);
  EXPECT_GT(reference.tail(2).norm(), 0.0);

  std::map<uint32_t, int> slot;
  for (size_t k = 0; k < all.image_ids.size(); ++k) slot[all.image_ids[k]] = static_cast<int>(k);
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(reference.size());
  double cost = 0.0;
  for (size_t m = 0; m < motions.size(); ++m) {
    const LocalHessian h = ComputeLocalHessian(rec, motions[m], static_cast<int>(m), lh, nullptr, &free);
    ASSERT_EQ(h.status, LocalHessianStatus::kOk) << m;
    for (int a = 0; a < h.num_views(); ++a)
      sum.segment<6>(6 * slot.at(h.image_ids[a])) += h.reduced_gradient.segment<6>(6 * a);
    sum.tail(2) += h.reduced_gradient.tail(2);
    cost += h.robust_cost;
  }
  EXPECT_LE((sum - reference).head(n).norm(), 1e-9 * reference.head(n).norm());
  EXPECT_LE((sum - reference).tail(2).norm(), 1e-9 * reference.tail(2).norm());
  // The true cost the re-linearisation checks adds up too.
  EXPECT_NEAR(cost, whole.robust_cost, 1e-9 * whole.robust_cost);
}

}  // namespace
}  // namespace pgba
