// N-view relative motions (local_motions.h): which views a motion takes, the local BA that
// converges it, and its 6N x 6N local Hessian.
#include "modules/local_hessian/local_motions.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <set>

#include "modules/local_hessian/local_bundle.h"
#include "modules/local_hessian/reduced_camera_matrix.h"
#include "pgba/geometry/rotation.h"
#include "tests/global_ba/global_ba_fixture.h"
#include "tests/local_hessian/dense_reference.h"
#include "tests/local_hessian/ring_scene.h"

namespace pgba {
namespace {

using testing::MakeRingScene;
using testing::PosesOf;
using testing::RingSceneOptions;

Reconstruction Ring(double noise_px, uint64_t seed, int num_points = 2500) {
  RingSceneOptions o;
  o.num_images = 20;
  o.num_points = num_points;
  o.noise_px = noise_px;
  o.seed = seed;
  return MakeRingScene(o);
}

// Tracks the two images share.
int Shared(const Reconstruction& rec, uint32_t a, uint32_t b) {
  int n = 0;
  for (const auto& [id, pt] : rec.points3D) {
    bool sa = false, sb = false;
    for (const TrackElement& el : pt.track) {
      sa = sa || el.image_id == a;
      sb = sb || el.image_id == b;
    }
    n += sa && sb;
  }
  return n;
}

TEST(LocalMotions, EachImageWithItsBestConnectedNeighbours) {
  const Reconstruction rec = Ring(0.5, 3);
  const std::map<uint32_t, Pose> poses = PosesOf(rec);
  LocalMotionOptions o;
  o.views = 5;
  const std::vector<LocalMotion> motions = SelectLocalMotions(rec, poses, o);
  ASSERT_FALSE(motions.empty());
  std::set<std::vector<uint32_t>> sets;
  std::set<uint32_t> covered;
  for (const LocalMotion& m : motions) {
    ASSERT_EQ(m.num_views(), 5);
    ASSERT_EQ(m.local_poses.size(), 5u);
    std::vector<uint32_t> key = m.image_ids;
    std::sort(key.begin(), key.end());
    EXPECT_EQ(std::unique(key.begin(), key.end()), key.end()) << "an image twice";
    EXPECT_TRUE(sets.insert(key).second) << "the same image set twice";
    covered.insert(m.image_ids.begin(), m.image_ids.end());
    // The neighbours are the centre's best connected images, in decreasing order, and no
    // image outside the motion shares more tracks with the centre than the weakest of them.
    const uint32_t centre = m.image_ids[0];
    for (int k = 2; k < m.num_views(); ++k)
      EXPECT_GE(Shared(rec, centre, m.image_ids[k - 1]), Shared(rec, centre, m.image_ids[k]));
    const int weakest = Shared(rec, centre, m.image_ids.back());
    for (const auto& [id, pose] : poses) {
      if (std::find(m.image_ids.begin(), m.image_ids.end(), id) == m.image_ids.end()) {
        EXPECT_LE(Shared(rec, centre, id), weakest);
      }
    }
    // Its tracks: exactly those seen by two of its views or more.
    std::set<uint64_t> expected;
    for (const auto& [id, pt] : rec.points3D) {
      std::set<uint32_t> seen;
      for (const TrackElement& el : pt.track)
        if (std::find(m.image_ids.begin(), m.image_ids.end(), el.image_id) != m.image_ids.end())
          seen.insert(el.image_id);
      if (seen.size() >= 2) expected.insert(id);
    }
    EXPECT_EQ(std::set<uint64_t>(m.track_ids.begin(), m.track_ids.end()), expected);
  }
  EXPECT_EQ(covered.size(), poses.size());
  // Deterministic, and empty for the paper's triplets (views = 3: the triplets serve).
  const std::vector<LocalMotion> again = SelectLocalMotions(rec, poses, o);
  ASSERT_EQ(again.size(), motions.size());
  for (size_t i = 0; i < motions.size(); ++i) EXPECT_EQ(again[i].image_ids, motions[i].image_ids);
  o.views = 3;
  EXPECT_TRUE(SelectLocalMotions(rec, poses, o).empty());
}

// A stride of 2 takes every second neighbour of the ranking (i+1, i+2, i+3 rather than i+1,
// i-1, i+2 on a ring): the motion reaches further along the tracks than the stride-1 motion
// (mean largest chord 1.46x here).
TEST(LocalMotions, StridesSpreadAMotionAlongTheTracks) {
  const Reconstruction rec = Ring(0.5, 3);
  const std::map<uint32_t, Pose> poses = PosesOf(rec);
  LocalMotionOptions o;
  o.views = 4;
  o.neighbour_strides = {1, 2};
  const std::vector<LocalMotion> motions = SelectLocalMotions(rec, poses, o);
  o.neighbour_strides = {1};
  const size_t near = SelectLocalMotions(rec, poses, o).size();
  ASSERT_GT(motions.size(), near);
  auto span = [&](const LocalMotion& m) {  // largest centre distance from the motion's image
    double d = 0.0;
    for (const uint32_t id : m.image_ids) d = std::max(d, (poses.at(id).C() - poses.at(m.image_ids[0]).C()).norm());
    return d;
  };
  double near_span = 0.0, far_span = 0.0;
  for (size_t i = 0; i < motions.size(); ++i) (i < near ? near_span : far_span) += span(motions[i]);
  near_span /= near;
  far_span /= motions.size() - near;
  EXPECT_GT(far_span, 1.2 * near_span);
  for (size_t i = near; i < motions.size(); ++i) {
    // Every second neighbour: ranks 0, 2, 4 of the image's ranking.
    const LocalMotion& m = motions[i];
    const uint32_t c = m.image_ids[0];
    std::vector<std::pair<int, uint32_t>> ranked;
    for (const auto& [id, pose] : poses)
      if (id != c && Shared(rec, c, id) >= o.min_shared_tracks) ranked.emplace_back(-Shared(rec, c, id), id);
    std::sort(ranked.begin(), ranked.end());
    for (int k = 1; k < m.num_views(); ++k) EXPECT_EQ(m.image_ids[k], ranked[2 * (k - 1)].second);
  }
}

// From poses off by 0.05 deg (several pixels), a motion's local BA reaches the truth on a
// noise-free scene (up to the similarity of its frame), and its local Hessian is 6N x 6N
// with exactly the 7 similarity directions unseen.
TEST(LocalMotions, ConvergeToTheTruthAndSeeAllButTheSimilarity) {
  const Reconstruction rec = Ring(0.0, 5);
  const std::map<uint32_t, Pose> truth = PosesOf(rec);
  const std::map<uint32_t, Pose> start = testing::PerturbPoses(truth, 0.05, 1e-3, 9);
  LocalMotionOptions o;
  o.views = 6;
  std::vector<LocalMotion> motions = SelectLocalMotions(rec, start, o);
  ASSERT_GE(motions.size(), 3u);
  motions.resize(3);
  LocalHessianOptions lh = PaperTripletLocalHessianOptions();
  ConvergeLocalMotions(rec, lh, o, &motions);
  for (const LocalMotion& m : motions) {
    // Relative rotations and the shape of the centres (scale-free) against the truth.
    const Pose& a = m.local_poses[0];
    const Pose& b = m.local_poses[1];
    const double scale = (b.C() - a.C()).norm() / (truth.at(m.image_ids[1]).C() - truth.at(m.image_ids[0]).C()).norm();
    for (int k = 1; k < m.num_views(); ++k) {
      const Pose& tk = truth.at(m.image_ids[k]);
      const Pose& t0 = truth.at(m.image_ids[0]);
      EXPECT_LT(RotationAngleDeg(m.local_poses[k].R() * a.R().transpose(), tk.R() * t0.R().transpose()), 1e-6);
      // Centre of view k in view 0's camera frame, over the scale.
      const Eigen::Vector3d local = a.R() * (m.local_poses[k].C() - a.C()) / scale;
      const Eigen::Vector3d expected = t0.R() * (tk.C() - t0.C());
      EXPECT_LT((local - expected).norm(), 1e-6 * expected.norm()) << "view " << k;
    }
    const LocalHessian h = ComputeLocalHessian(rec, m, 0, lh);
    ASSERT_EQ(h.status, LocalHessianStatus::kOk);
    ASSERT_EQ(h.h.rows(), 36);
    EXPECT_EQ(h.newton_step.size(), 36);
    const Eigen::MatrixXd h_points = h.h.Dense() - h.Prior();
    const Eigen::VectorXd ev = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(h_points).eigenvalues();
    // Scale-free test of the rank: 7 null directions, then a clear gap (the rank test of
    // ComputeGaugePrior sees the same in its scaled chart).
    EXPECT_LT(std::abs(ev(6)), 1e-9 * ev(35));
    EXPECT_GT(h.eigenvalue_ratio, 1e-8);
  }
}

// (a) of the triplets for a motion of five views: h is the inverse of the camera block of
// the dense covariance of its own local BA (Ceres' Jacobian, inverted densely).
TEST(LocalMotions, HessianEqualsInverseOfCameraBlockOfDenseCovariance) {
  const Reconstruction rec = Ring(0.5, 7, 900);  // a dense inverse of every point: keep it small
  LocalMotionOptions o;
  o.views = 5;
  std::vector<LocalMotion> motions = SelectLocalMotions(rec, PosesOf(rec), o);
  ASSERT_FALSE(motions.empty());
  LocalHessianOptions opt = PaperTripletLocalHessianOptions();
  opt.solver.max_iterations = 10;
  LocalBundleProblem p;
  ASSERT_EQ(BuildLocalBundleProblem(rec, motions[0], opt, &p), LocalHessianStatus::kOk);
  ASSERT_TRUE(SolveLocalBundle(opt.solver, &p));
  const ReducedCameraSystem red = ReducedCameraMatrix(p);
  const GaugePrior prior = ComputeGaugePrior(red.h, p.poses, MedianDepth(p), opt);
  const Eigen::MatrixXd h = red.h + prior.P;
  const int n = 30;
  ASSERT_EQ(h.rows(), n);

  const Eigen::MatrixXd cov = testing::DenseCovariance(p, prior.P);
  ASSERT_GT(cov.rows(), n);
  const Eigen::MatrixXd h_ref = cov.topLeftCorner(n, n).fullPivLu().inverse();
  // Scale-aware relative difference (positions by the depth, as for the triplets).
  EXPECT_LT(testing::RelativeDifference(h, h_ref, MedianDepth(p)), 1e-6);
}

}  // namespace
}  // namespace pgba
