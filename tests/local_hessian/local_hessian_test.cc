// Local Hessian: h against independent references (dense covariance of the full problem,
// point-based cost with re-optimised points), rejection reasons, determinism.
#include "modules/local_hessian/local_hessian.h"

#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cstdio>
#include <random>

#include "modules/local_hessian/local_bundle.h"
#include "modules/local_hessian/reduced_camera_matrix.h"
#include "tests/local_hessian/dense_reference.h"
#include "tests/local_hessian/ring_scene.h"

namespace pgba {
namespace {

using testing::CostWithPointsOptimised;
using testing::DenseCovariance;
using testing::MakeRingScene;
using testing::MakeTriplet;
using testing::RelativeDifference;
using testing::RingSceneOptions;

// (a) h is the inverse of the camera block of the covariance of the full problem, built
// independently: Ceres' own Jacobian (Problem::Evaluate, with the Huber loss correction),
// H = J^T J + prior, inverted densely.
TEST(LocalHessian, EqualsInverseOfCameraBlockOfDenseCovariance) {
  RingSceneOptions so;
  so.num_points = 600;
  so.seed = 11;
  const Reconstruction rec = MakeRingScene(so);
  std::mt19937_64 rng(3);
  const LocalMotion t = MakeTriplet(rec, {1, 2, 4}, rng);
  LocalHessianOptions opt = PaperTripletLocalHessianOptions();
  opt.solver.max_iterations = 5;
  LocalBundleProblem p;
  ASSERT_EQ(BuildLocalBundleProblem(rec, t, opt, &p), LocalHessianStatus::kOk);
  // Push some observations into Huber's linear branch (1 px < error < 4 px), so that the
  // IRLS weighting is exercised.
  int pushed = 0;
  for (size_t i = 0; i < p.observations.size(); i += 7, ++pushed) p.observations[i].pixel += Eigen::Vector2d(1.6, -1.5);
  ASSERT_TRUE(SolveLocalBundle(opt.solver, &p));
  const ReducedCameraSystem red = ReducedCameraMatrix(p);
  const double L = MedianDepth(p);
  const GaugePrior prior = ComputeGaugePrior(red.h, p.poses, L, opt);
  const Matrix18d h = red.h + prior.P;

  // Dense reference.
  int outside_huber = 0;
  for (const LocalObservation& o : p.observations) {
    const ReprojectionError e(p.cameras[o.view], p.poses[o.view].R0, o.pixel);
    double r[2];
    e(p.poses[o.view].x.data(), p.points[o.point].data(), r);
    outside_huber += std::hypot(r[0], r[1]) > p.loss.scale;
  }
  EXPECT_GT(outside_huber, 10);
  const Eigen::MatrixXd cov = DenseCovariance(p, prior.P);
  ASSERT_GT(cov.rows(), 18);
  const Matrix18d h_ref = cov.topLeftCorner<18, 18>().fullPivLu().inverse();
  const double diff = RelativeDifference(h, h_ref, L);
  EXPECT_LT(diff, 1e-6) << "points " << p.points.size();
  // The camera covariance itself, compared where it is well determined (not in the
  // prior-held gauge directions): the eigenvectors of h with large eigenvalues.
  Eigen::MatrixXd V;
  Eigen::VectorXd D;
  DecomposeReducedMatrix(h, &V, &D);
  for (int j = 7; j < 18; ++j) {
    const Vector18d v = V.row(j).transpose();
    const double var_h = 1.0 / (D(j) * D(j));
    const double var_ref = v.dot(cov.topLeftCorner<18, 18>() * v);
    EXPECT_NEAR(var_ref / var_h, 1.0, 1e-5) << "eigen direction " << j;
  }
  // Decomposition reproduces h.
  EXPECT_LT(RelativeDifference(V.transpose() * D.cwiseAbs2().asDiagonal() * V, h, L), 1e-12);
}

// (c) On a noise-free triplet, moving the cameras along an eigenvector of h by epsilon
// raises the point-based cost (points re-optimised) by epsilon^2 lambda / 2 (second order);
// along the 7 similarity directions (gauge) it does not raise it at all.
TEST(LocalHessian, PredictsPointBasedCostAlongEigenvectors) {
  RingSceneOptions so;
  so.num_points = 600;
  so.noise_px = 0.0;
  so.seed = 5;
  const Reconstruction rec = MakeRingScene(so);
  std::mt19937_64 rng(9);
  const LocalMotion t = MakeTriplet(rec, {3, 4, 6}, rng);
  const LocalHessianOptions opt = PaperTripletLocalHessianOptions();
  const LocalHessian lh = ComputeLocalHessian(rec, t, 0, opt);
  ASSERT_EQ(lh.status, LocalHessianStatus::kOk);
  EXPECT_LT(lh.rms_px, 1e-6);
  EXPECT_GT(lh.num_points, 50);
  // The same observations and points, for the re-optimisation.
  LocalMotion t0 = t;
  t0.local_poses = lh.local_poses;
  LocalBundleProblem p;
  ASSERT_EQ(BuildLocalBundleProblem(rec, t0, opt, &p), LocalHessianStatus::kOk);
  EXPECT_LT(CostWithPointsOptimised(p, lh.local_poses), 1e-18);

  const Matrix18d h0 = lh.h.Dense() - lh.Prior();  // h without the gauge prior
  Eigen::MatrixXd V;
  Eigen::VectorXd D;
  lh.Factor(&V, &D);
  const double lambda_max = D(17) * D(17);
  const double target = 1e-4;  // cost increase aimed at (weighted px^2)
  auto move = [&](const Vector18d& v, double eps) {
    std::vector<Pose> moved(3);
    for (int k = 0; k < 3; ++k) {
      const Pose& x0 = lh.local_poses[k];
      moved[k] = Pose::FromRC(x0.R() * ExpSO3(eps * v.segment<3>(6 * k + 3)), x0.C() + eps * v.segment<3>(6 * k));
    }
    return moved;
  };
  int informative = 0;
  for (int j = 0; j < 18; ++j) {
    const Vector18d v = V.row(j).transpose();
    const double curvature = v.dot(h0 * v);  // what h (without its prior) predicts
    if (curvature < 1e-7 * lambda_max) continue;  // (nearly) a pure gauge direction: below
    ++informative;
    const double eps = std::sqrt(2.0 * target / curvature);
    const double actual = CostWithPointsOptimised(p, move(v, eps));
    EXPECT_NEAR(actual / (0.5 * eps * eps * curvature), 1.0, 2e-3) << "eigen direction " << j;
  }
  EXPECT_GE(informative, 11);
  // Along the similarity generators the point-based cost does not rise at all (gauge); h
  // without its prior predicts exactly that.
  std::vector<PoseBlock> x0(3);
  for (int k = 0; k < 3; ++k) x0[k] = PoseBlock::FromPose(lh.local_poses[k]);
  const Eigen::Matrix<double, 18, 7> G = SimilarityGenerators(x0, 1.0);
  for (int i = 0; i < 7; ++i) {
    const Vector18d g = G.col(i).normalized();
    const double eps = std::sqrt(2.0 * target / lambda_max);
    EXPECT_LT(CostWithPointsOptimised(p, move(g, eps)), 1e-5 * target) << "generator " << i;
    EXPECT_LT(g.dot(h0 * g), 1e-9 * lambda_max) << "generator " << i;
  }
}

TEST(LocalHessian, DecompositionAndPriorAreConsistent) {
  RingSceneOptions so;
  so.num_points = 500;
  const Reconstruction rec = MakeRingScene(so);
  std::mt19937_64 rng(1);
  const LocalMotion t = MakeTriplet(rec, {7, 8, 9}, rng);
  const LocalHessian lh = ComputeLocalHessian(rec, t, 4, PaperTripletLocalHessianOptions());
  ASSERT_EQ(lh.status, LocalHessianStatus::kOk);
  EXPECT_EQ(lh.motion_index, 4);
  Eigen::MatrixXd V;
  Eigen::VectorXd D;
  lh.Factor(&V, &D);
  EXPECT_LT(RelativeDifference(V.transpose() * D.cwiseAbs2().asDiagonal() * V, lh.h.Dense(), lh.depth_scale), 1e-12);
  EXPECT_LT((V * V.transpose() - Matrix18d::Identity()).norm(), 1e-12);
  // The similarity generators span the null space of h without the prior (the gauge), and
  // the default prior lives on them only: it leaves the informative directions untouched.
  std::vector<PoseBlock> x0(3);
  for (int k = 0; k < 3; ++k) x0[k] = PoseBlock::FromPose(lh.local_poses[k]);
  const Eigen::Matrix<double, 18, 7> G = SimilarityGenerators(x0, 1.0);
  const Matrix18d h0 = lh.h.Dense() - lh.Prior();
  for (int i = 0; i < 7; ++i)
    EXPECT_LT((h0 * G.col(i)).norm(), 1e-8 * h0.norm() * G.col(i).norm()) << "generator " << i;
  // Once the similarity absorbs the gauge directions (as in the global BA), the prior adds
  // nothing: h reduced over span(G) equals h without the prior.
  auto reduce_gauge = [&](const Matrix18d& h) -> Matrix18d {
    const Eigen::Matrix<double, 18, 7> hG = h * G;
    return h - hG * (G.transpose() * hG).inverse() * hG.transpose();
  };
  EXPECT_LT((reduce_gauge(lh.h.Dense()) - h0).norm(), 1e-9 * h0.norm());
  // mu = 1e-3 of the largest eigenvalue in the scale-aware chart [c / L, omega].
  Vector18d sc;
  for (int k = 0; k < 3; ++k) sc.segment<6>(6 * k) << lh.depth_scale, lh.depth_scale, lh.depth_scale, 1, 1, 1;
  const double lmax = Eigen::SelfAdjointEigenSolver<Matrix18d>(sc.asDiagonal() * h0 * sc.asDiagonal()).eigenvalues()(17);
  EXPECT_NEAR(lh.prior_mu / lmax, 1e-3, 1e-12);
  // The isotropic prior of the ARCHITECTURE lesson: mu / L^2 on centres, mu on rotations.
  LocalHessianOptions iso = PaperTripletLocalHessianOptions();
  iso.prior_shape = PriorShape::kIsotropic;
  iso.prior_relative = 1e-6;
  const LocalHessian li = ComputeLocalHessian(rec, t, 4, iso);
  ASSERT_EQ(li.status, LocalHessianStatus::kOk);
  EXPECT_NEAR(li.prior_mu / lmax, 1e-6, 1e-15);
  EXPECT_NEAR(li.Prior()(0, 0) * li.depth_scale * li.depth_scale / li.prior_mu, 1.0, 1e-12);
  EXPECT_NEAR(li.Prior()(3, 3) / li.prior_mu, 1.0, 1e-12);
  const Eigen::MatrixXd off_diagonal = li.Prior() - Eigen::MatrixXd(li.Prior().diagonal().asDiagonal());
  EXPECT_EQ(off_diagonal.norm(), 0.0);  // diagonal
  EXPECT_LT((li.h.Dense() - li.Prior() - h0).norm(), 1e-12 * h0.norm());  // same h without the prior
  // ... but the isotropic prior also weighs the informative directions (a small bias).
  EXPECT_GT((reduce_gauge(li.h.Dense()) - h0).norm(), 1e-9 * h0.norm());
  // Q = inf: weight 1, h scales up by (M + Q) / Q.
  LocalHessianOptions no_att = PaperTripletLocalHessianOptions();
  no_att.attenuation_q = std::numeric_limits<double>::infinity();
  const LocalHessian full = ComputeLocalHessian(rec, t, 4, no_att);
  ASSERT_EQ(full.status, LocalHessianStatus::kOk);
  EXPECT_EQ(full.observation_weight, 1.0);
  EXPECT_NEAR(full.h(3, 3) / lh.h(3, 3), (lh.num_points + 10.0) / 10.0, 1e-3 * (lh.num_points + 10.0) / 10.0);
  // One local BA iteration from the true poses on noisy data leaves a small reduced gradient
  // (a converged x0); more iterations shrink it further.
  LocalHessianOptions many = PaperTripletLocalHessianOptions();
  many.solver.max_iterations = 10;
  const LocalHessian conv = ComputeLocalHessian(rec, t, 4, many);
  EXPECT_LT(conv.reduced_gradient.norm(), lh.reduced_gradient.norm() + 1e-12);
}

TEST(LocalHessian, RejectsWithCountedReasons) {
  RingSceneOptions so;
  so.num_points = 400;
  const Reconstruction rec = MakeRingScene(so);
  std::mt19937_64 rng(2);
  std::vector<LocalMotion> triplets;
  triplets.push_back(MakeTriplet(rec, {1, 2, 3}, rng));  // ok
  LocalMotion few = triplets[0];
  few.track_ids.resize(20);  // < 30 points
  triplets.push_back(few);
  LocalMotion missing = triplets[0];
  missing.image_ids[2] = 999;  // not in the model
  triplets.push_back(missing);
  LocalMotion nan_pose = triplets[0];
  nan_pose.local_poses[1] = Pose::FromRC(Eigen::Matrix3d::Identity(), Eigen::Vector3d(NAN, 0, 0));
  triplets.push_back(nan_pose);
  LocalMotion dup = triplets[0];
  dup.image_ids[1] = dup.image_ids[0];
  triplets.push_back(dup);
  LocalHessianOptions opt = PaperTripletLocalHessianOptions();
  const LocalHessianResult r = ComputeLocalHessians(rec, triplets, opt);
  ASSERT_EQ(r.hessians.size(), triplets.size());
  EXPECT_EQ(r.hessians[0].status, LocalHessianStatus::kOk);
  EXPECT_EQ(r.hessians[1].status, LocalHessianStatus::kTooFewPoints);
  EXPECT_EQ(r.hessians[2].status, LocalHessianStatus::kInvalidInput);
  EXPECT_EQ(r.hessians[3].status, LocalHessianStatus::kInvalidInput);
  EXPECT_EQ(r.hessians[4].status, LocalHessianStatus::kInvalidInput);
  EXPECT_EQ(r.num_ok(), 1);
  EXPECT_EQ(r.status_counts[static_cast<int>(LocalHessianStatus::kInvalidInput)], 3);
  // A demanding conditioning bar rejects as ill-conditioned.
  opt.min_eigenvalue_ratio = 0.5;
  EXPECT_EQ(ComputeLocalHessian(rec, triplets[0], 0, opt).status, LocalHessianStatus::kIllConditioned);
}

// A view that observes only two of the triplet's points cannot be resected: h has a null
// space beyond the 7-dim similarity gauge and the triplet is rejected as ill-conditioned
// rather than passed on with a meaningless h.
TEST(LocalHessian, RejectsRankDeficientGeometry) {
  RingSceneOptions so;
  so.num_points = 600;
  Reconstruction rec = MakeRingScene(so);
  std::mt19937_64 rng(4);
  const LocalMotion t = MakeTriplet(rec, {1, 2, 3}, rng);
  ASSERT_GT(t.track_ids.size(), 40u);
  for (size_t i = 2; i < t.track_ids.size(); ++i) {
    auto& track = rec.points3D.at(t.track_ids[i]).track;
    track.erase(std::remove_if(track.begin(), track.end(), [](const TrackElement& el) { return el.image_id == 3; }),
                track.end());
  }
  const LocalHessian lh = ComputeLocalHessian(rec, t, 0, PaperTripletLocalHessianOptions());
  EXPECT_EQ(lh.status, LocalHessianStatus::kIllConditioned) << LocalHessianStatusName(lh.status);
  EXPECT_LT(lh.eigenvalue_ratio, 1e-10);
}

TEST(LocalHessian, ParallelResultIsDeterministic) {
  RingSceneOptions so;
  so.num_points = 800;
  const Reconstruction rec = MakeRingScene(so);
  std::mt19937_64 rng(8);
  const std::vector<LocalMotion> triplets = testing::MakeRingTriplets(rec, 4, true, rng);
  LocalHessianOptions opt = PaperTripletLocalHessianOptions();
  const LocalHessianResult par = ComputeLocalHessians(rec, triplets, opt);
  opt.num_threads = 1;
  const LocalHessianResult seq = ComputeLocalHessians(rec, triplets, opt);
  ASSERT_EQ(par.hessians.size(), triplets.size());
  EXPECT_EQ(par.num_ok(), static_cast<int>(triplets.size()));
  for (size_t i = 0; i < triplets.size(); ++i) {
    EXPECT_TRUE(par.hessians[i].h == seq.hessians[i].h);
    EXPECT_EQ(par.hessians[i].motion_index, static_cast<int>(i));
  }
}

// The Newton step -h^-1 g (paper eq. 3) of the quadratic model: about zero at a converged
// local BA; from a linearisation point away from the optimum (h and g there, no iteration)
// it lands where the local BA converges, up to second order.
TEST(LocalHessian, NewtonStepPointsToTheTripletOptimum) {
  RingSceneOptions so;
  so.num_points = 800;
  so.seed = 21;
  const Reconstruction rec = MakeRingScene(so);
  std::mt19937_64 rng(22);
  LocalMotion t = MakeTriplet(rec, {2, 3, 5}, rng);
  LocalHessianOptions converge = PaperTripletLocalHessianOptions();
  converge.solver.max_iterations = 50;
  const LocalHessian opt = ComputeLocalHessian(rec, t, 0, converge);
  ASSERT_EQ(opt.status, LocalHessianStatus::kOk);
  const Matrix18d h0 = opt.h.Dense() - opt.Prior();
  auto whitened = [&](const Vector18d& v) { return std::sqrt(v.dot(h0 * v) / opt.observation_weight); };
  EXPECT_LT(whitened(opt.newton_step), 1e-2);  // px-units: converged

  // Linearise at the optimum moved along informative directions (0.02 deg, 1% of the baseline).
  LocalMotion moved = t;
  std::normal_distribution<double> n(0.0, 1.0);
  const double baseline = (opt.local_poses[1].C() - opt.local_poses[0].C()).norm();
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d w(n(rng), n(rng), n(rng)), d(n(rng), n(rng), n(rng));
    moved.local_poses[k] = Pose::FromRC(opt.local_poses[k].R() * ExpSO3(3.5e-4 * w.normalized()),
                                        opt.local_poses[k].C() + 0.01 * baseline * d.normalized());
  }
  LocalHessianOptions at_point = PaperTripletLocalHessianOptions();
  at_point.solver.max_iterations = 0;
  const LocalHessian lin = ComputeLocalHessian(rec, moved, 0, at_point);
  ASSERT_EQ(lin.status, LocalHessianStatus::kOk);
  std::vector<Pose> stepped(3);
  for (int k = 0; k < 3; ++k) {
    const Pose& y = lin.local_poses[k];
    stepped[k] = Pose::FromRC(y.R() * ExpSO3(lin.newton_step.segment<3>(6 * k + 3)),
                              y.C() + lin.newton_step.segment<3>(6 * k));
  }
  // Excess of the point-based cost (points re-optimised) over the optimum's.
  LocalMotion t0 = t;
  t0.local_poses = opt.local_poses;
  LocalBundleProblem p;
  ASSERT_EQ(BuildLocalBundleProblem(rec, t0, converge, &p), LocalHessianStatus::kOk);
  const double at_opt = CostWithPointsOptimised(p, opt.local_poses);
  const double excess_moved = CostWithPointsOptimised(p, lin.local_poses) - at_opt;
  const double excess_stepped = CostWithPointsOptimised(p, stepped) - at_opt;
  std::printf("cost excess over the optimum: linearisation point %.4g, after the Newton step %.4g\n", excess_moved,
              excess_stepped);
  EXPECT_GT(excess_moved, 1e-3);
  EXPECT_LT(excess_stepped, 0.02 * excess_moved);
  EXPECT_GT(whitened(lin.newton_step), 10.0 * whitened(opt.newton_step));
}

// shared_observation_weighting: each observation weighs 1 / (number of triplets using it).
TEST(LocalHessian, SharedObservationWeightingCountsTheTripletsOfEachObservation) {
  RingSceneOptions so;
  so.num_images = 16;
  so.num_points = 1500;
  so.seed = 23;
  const Reconstruction rec = MakeRingScene(so);
  std::mt19937_64 rng(24);
  const std::vector<LocalMotion> triplets = testing::MakeRingTriplets(rec, 4, false, rng);
  const ObservationShares shares = CountObservationShares(rec, triplets);
  // Brute force for every (image, track) of the triplets.
  for (const auto& [key, count] : shares) {
    int expected = 0;
    for (const LocalMotion& t : triplets) {
      const bool has_image = std::find(t.image_ids.begin(), t.image_ids.end(), key.first) != t.image_ids.end();
      const bool has_track = std::find(t.track_ids.begin(), t.track_ids.end(), key.second) != t.track_ids.end();
      expected += has_image && has_track;
    }
    ASSERT_EQ(count, expected);
  }
  LocalHessianOptions shared = PaperTripletLocalHessianOptions();
  shared.shared_observation_weighting = true;
  const LocalHessianResult plain = ComputeLocalHessians(rec, triplets, PaperTripletLocalHessianOptions());
  const LocalHessianResult weighted = ComputeLocalHessians(rec, triplets, shared);
  const LocalHessianResult given = ComputeLocalHessians(rec, triplets, shared, &shares);
  EXPECT_GE(weighted.num_ok(), static_cast<int>(triplets.size()) / 2);
  for (size_t i = 0; i < triplets.size(); ++i) {
    ASSERT_EQ(weighted.hessians[i].status, plain.hessians[i].status);
    if (plain.hessians[i].status != LocalHessianStatus::kOk) continue;
    // Interior triplets share their observations with others: lighter than unshared.
    EXPECT_LT(weighted.hessians[i].observation_weight, plain.hessians[i].observation_weight);
    EXPECT_GT(weighted.hessians[i].observation_weight, plain.hessians[i].observation_weight / 6.0);
    EXPECT_TRUE(weighted.hessians[i].h == given.hessians[i].h);
  }
}

TEST(LocalHessian, OptionsRoundTripThroughJson) {
  LocalHessianOptions o;
  o.attenuation_q = 25;
  o.prior_placement = PriorPlacement::kLocalBAAndHessian;
  const nlohmann::json j = o;
  const LocalHessianOptions back = j.get<LocalHessianOptions>();
  EXPECT_EQ(back.attenuation_q, 25);
  EXPECT_EQ(back.prior_placement, PriorPlacement::kLocalBAAndHessian);
  EXPECT_EQ(nlohmann::json::parse(R"({"huber_px": 2})").get<LocalHessianOptions>().solver.max_iterations, 0);
}

}  // namespace
}  // namespace pgba
