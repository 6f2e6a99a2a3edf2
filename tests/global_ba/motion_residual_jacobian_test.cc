// MotionResidual composes its Jacobian by hand (per-view Jets through ViewDeviation, then the
// columns of W in doubles, motion_residual.h). Checked on random motions (3 and 5 views, with
// and without intrinsic blocks, dense and factored W = diag(d) V) against two independent
// truths:
//   1. the residual r = W (dx - n) with dx written here from the paper's eq. 4 in plain Eigen
//      (c_k = lambda alpha (C_k - G) + beta, r_k = R0_k Exp(omega_k) alpha^T,
//      dx_k = [c_k - c0_k ; Log(r0_k^T r_k)], dx_kappa = kappa - kappa0), and its Jacobian by
//      central differences of that formula, step 1e-6;
//   2. ceres::GradientChecker (Ridders' extrapolated numeric differentiation of the cost
//      function itself).
#include "modules/global_ba/motion_residual.h"

#include <ceres/jet.h>
#include <gtest/gtest.h>

#include <Eigen/QR>
#include <iostream>
#include <random>
#include <stdexcept>

#include "pgba/geometry/rotation.h"

namespace pgba {
namespace {

struct RandomMotion {
  int n = 3;
  std::vector<int> intrinsic_sizes;
  std::vector<Eigen::Matrix3d> R0;
  std::vector<Pose> x0;
  MotionSimilarity sim;
  Eigen::MatrixXd W;  // dense truth
  Eigen::VectorXd d;
  Eigen::MatrixXd V;
  Eigen::VectorXd newton, kappa0;
  // Parameter values: poses (6 each), sim (7), intrinsics.
  std::vector<Eigen::VectorXd> blocks;
};

Eigen::Vector3d Gauss(std::mt19937& rng, double sd) {
  std::normal_distribution<double> g(0.0, sd);
  return Eigen::Vector3d(g(rng), g(rng), g(rng));
}

RandomMotion MakeMotion(int n, std::vector<int> intrinsic_sizes, unsigned seed) {
  std::mt19937 rng(seed);
  RandomMotion m;
  m.n = n;
  m.intrinsic_sizes = std::move(intrinsic_sizes);
  int K = 0;
  for (int s : m.intrinsic_sizes) K += s;
  const int rows = 6 * n + K;
  m.sim.alpha0 = ExpSO3(Gauss(rng, 1.5));
  // Local and global rotations in arbitrary frames, but agreeing through alpha0 up to ~0.35
  // rad (as after the averaging), so that no deviation comes near the angle pi, where Log
  // is not smooth.
  for (int k = 0; k < n; ++k) {
    m.x0.push_back(Pose::FromRC(ExpSO3(Gauss(rng, 1.5)), Gauss(rng, 2.0)));
    m.R0.push_back(m.x0[k].R() * m.sim.alpha0 * ExpSO3(Gauss(rng, 0.2)));
  }
  m.sim.G = Gauss(rng, 3.0);
  m.sim.x << Gauss(rng, 1.0), Gauss(rng, 0.2), 1.3;
  // A well-conditioned random W = diag(d) V, V orthonormal (as the local Hessian's).
  m.V = Eigen::HouseholderQR<Eigen::MatrixXd>(Eigen::MatrixXd::Random(rows, rows)).householderQ();
  m.d = Eigen::VectorXd::LinSpaced(rows, 0.5, 30.0);
  m.W = m.d.asDiagonal() * m.V;
  m.newton = Eigen::VectorXd::Random(rows) * 0.01;
  m.kappa0 = Eigen::VectorXd::Random(K) * 0.1 + Eigen::VectorXd::Constant(K, 1.0);
  // The point of evaluation: poses away from their reference (omega up to ~0.3 rad), the
  // similarity away from alpha0, intrinsics away from kappa0.
  for (int k = 0; k < n; ++k) {
    Eigen::VectorXd b(6);
    b << m.x0[k].C() + Gauss(rng, 1.0), Gauss(rng, 0.2);
    m.blocks.push_back(b);
  }
  Eigen::VectorXd s(7);
  s << Gauss(rng, 1.0), Gauss(rng, 0.2), 0.8;
  m.blocks.push_back(s);
  for (int c = 0, row = 0; c < static_cast<int>(m.intrinsic_sizes.size()); row += m.intrinsic_sizes[c], ++c)
    m.blocks.push_back(m.kappa0.segment(row, m.intrinsic_sizes[c]) + Eigen::VectorXd::Random(m.intrinsic_sizes[c]) * 0.05);
  return m;
}

// The residual from eq. 4 and 5, written independently of motion_residual.cc.
Eigen::VectorXd ResidualByFormula(const RandomMotion& m, const std::vector<Eigen::VectorXd>& b) {
  const Eigen::VectorXd& s = b[m.n];
  const Eigen::Matrix3d alpha = m.sim.alpha0 * ExpSO3(s.segment<3>(3));
  Eigen::VectorXd dx(m.W.rows());
  for (int k = 0; k < m.n; ++k) {
    const Eigen::Vector3d C = b[k].head<3>();
    dx.segment<3>(6 * k) = s(6) * alpha * (C - m.sim.G) + s.head<3>() - m.x0[k].C();
    const Eigen::Matrix3d r = m.R0[k] * ExpSO3(b[k].tail<3>()) * alpha.transpose();
    dx.segment<3>(6 * k + 3) = LogSO3(m.x0[k].R().transpose() * r);
  }
  for (int c = 0, row = 0; c < static_cast<int>(m.intrinsic_sizes.size()); row += m.intrinsic_sizes[c], ++c)
    dx.segment(6 * m.n + row, m.intrinsic_sizes[c]) = b[m.n + 1 + c] - m.kappa0.segment(row, m.intrinsic_sizes[c]);
  return m.W * (dx - m.newton);
}

std::unique_ptr<MotionResidual> MakeResidual(const RandomMotion& m, bool factored) {
  MotionWeight W = factored ? MotionWeight(std::make_shared<const Eigen::VectorXd>(m.d),
                                           std::make_shared<const Eigen::MatrixXd>(m.V))
                            : MotionWeight::Dense(m.W);
  return std::make_unique<MotionResidual>(m.R0, m.sim, m.x0, std::move(W), m.newton, m.kappa0, m.intrinsic_sizes);
}

struct Case {
  int n;
  std::vector<int> intrinsic_sizes;
  bool factored;
};

void PrintTo(const Case& c, std::ostream* os) {
  *os << c.n << " views, " << c.intrinsic_sizes.size() << " cameras, " << (c.factored ? "factored" : "dense") << " W";
}

class MotionResidualJacobian : public ::testing::TestWithParam<Case> {};

TEST_P(MotionResidualJacobian, MatchesCentralDifferencesOfEq4AndCeresGradientChecker) {
  const Case& c = GetParam();
  double worst_value = 0.0, worst_jacobian = 0.0, worst_checker = 0.0;
  for (unsigned seed = 1; seed <= 10; ++seed) {
    const RandomMotion m = MakeMotion(c.n, c.intrinsic_sizes, seed + 100 * c.n);
    const std::unique_ptr<MotionResidual> cost = MakeResidual(m, c.factored);
    const int rows = static_cast<int>(m.W.rows());
    ASSERT_EQ(cost->num_residuals(), rows);
    ASSERT_EQ(cost->parameter_block_sizes().size(), m.blocks.size());

    std::vector<const double*> params;
    for (const Eigen::VectorXd& b : m.blocks) params.push_back(b.data());
    std::vector<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> J(m.blocks.size());
    std::vector<double*> jac;
    for (size_t i = 0; i < m.blocks.size(); ++i) {
      J[i].resize(rows, m.blocks[i].size());
      jac.push_back(J[i].data());
    }
    Eigen::VectorXd r(rows), r_nojac(rows);
    ASSERT_TRUE(cost->Evaluate(params.data(), r.data(), jac.data()));
    ASSERT_TRUE(cost->Evaluate(params.data(), r_nojac.data(), nullptr));
    const Eigen::VectorXd r_truth = ResidualByFormula(m, m.blocks);
    worst_value = std::max(worst_value, (r - r_truth).norm() / r_truth.norm());
    EXPECT_LT((r_nojac - r).norm(), 1e-12 * r.norm());

    // 1. Central differences of the independent formula, block by block.
    constexpr double h = 1e-6;
    for (size_t i = 0; i < m.blocks.size(); ++i) {
      Eigen::MatrixXd numeric(rows, m.blocks[i].size());
      for (int j = 0; j < m.blocks[i].size(); ++j) {
        std::vector<Eigen::VectorXd> plus = m.blocks, minus = m.blocks;
        plus[i](j) += h;
        minus[i](j) -= h;
        numeric.col(j) = (ResidualByFormula(m, plus) - ResidualByFormula(m, minus)) / (2 * h);
      }
      const double err = (Eigen::MatrixXd(J[i]) - numeric).norm() / numeric.norm();
      worst_jacobian = std::max(worst_jacobian, err);
      EXPECT_LT(err, 1e-8) << "seed " << seed << " block " << i;
    }

    // 2. Ceres' own checker on the cost function.
    ceres::NumericDiffOptions nd;
    const std::vector<const ceres::Manifold*>* no_manifolds = nullptr;
    const ceres::GradientChecker checker(cost.get(), no_manifolds, nd);
    ceres::GradientChecker::ProbeResults results;
    EXPECT_TRUE(checker.Probe(params.data(), 1e-7, &results)) << results.error_log;
    EXPECT_LT(results.maximum_relative_error, 1e-8);
    worst_checker = std::max(worst_checker, results.maximum_relative_error);
  }
  // Measured (10 seeds per case): residual 3-5e-16 relative, Jacobian 1.2-1.7e-9 relative to
  // the central differences (their own truncation and rounding error at h = 1e-6).
  EXPECT_LT(worst_value, 1e-14);
  std::cout << "n " << c.n << " K " << c.intrinsic_sizes.size() << (c.factored ? " factored" : " dense")
            << ": worst residual " << worst_value << ", worst Jacobian " << worst_jacobian
            << ", GradientChecker " << worst_checker << "\n";
}

INSTANTIATE_TEST_SUITE_P(Motions, MotionResidualJacobian,
                         ::testing::Values(Case{3, {}, false}, Case{3, {}, true}, Case{5, {}, true},
                                           Case{3, {1, 2}, false}, Case{4, {3}, true}),
                         [](const ::testing::TestParamInfo<Case>& info) {
                           const Case& c = info.param;
                           return std::to_string(c.n) + "views_" + std::to_string(c.intrinsic_sizes.size()) +
                                  "cameras_" + (c.factored ? "factored" : "dense");
                         });

// The closed-form 6 x 13 Jacobian of one view's deviation (ViewDeviation::Linearize) against
// forward-mode automatic differentiation of the same templated formula, at random points and
// at the linearisation point itself (omega = theta = 0, where the SO(3) Jacobians take their
// series branches).
TEST(ViewDeviationJacobian, ClosedFormMatchesAutomaticDifferentiation) {
  using Jet = ceres::Jet<double, 13>;
  std::mt19937 rng(7);
  for (int trial = 0; trial < 40; ++trial) {
    const bool at_reference = trial % 4 == 0;
    ViewDeviation view{ExpSO3(Gauss(rng, 1.5)), Gauss(rng, 3.0), ExpSO3(Gauss(rng, 0.3)), Gauss(rng, 2.0)};
    Eigen::Matrix<double, 6, 1> pose;
    Eigen::Matrix<double, 7, 1> sim;
    pose << Gauss(rng, 4.0), (at_reference ? Eigen::Vector3d::Zero() : Gauss(rng, 0.3));
    sim << Gauss(rng, 1.0), (at_reference ? Eigen::Vector3d::Zero() : Gauss(rng, 0.3)),
        0.5 + std::uniform_real_distribution<double>(0.0, 1.5)(rng);
    Jet jp[6], js[7], jd[6];
    for (int i = 0; i < 6; ++i) jp[i] = Jet(pose[i], i);
    for (int i = 0; i < 7; ++i) js[i] = Jet(sim[i], 6 + i);
    view(jp, js, jd);
    double dx[6];
    Eigen::Matrix<double, 6, 13> J;
    view.Linearize(pose.data(), sim.data(), dx, &J);
    for (int r = 0; r < 6; ++r) {
      EXPECT_NEAR(dx[r], jd[r].a, 1e-13 * (1.0 + std::abs(jd[r].a))) << "trial " << trial;
      for (int c = 0; c < 13; ++c)
        EXPECT_NEAR(J(r, c), jd[r].v(c), 1e-11 * (1.0 + std::abs(jd[r].v(c)))) << "trial " << trial << " (" << r
                                                                                  << ", " << c << ")";
    }
  }
}

// Held as its Gram matrix h = W^T W only, a residual gives the same |r|^2 and the same gradient
// W^T r with respect to the deviation as with W itself: the formula's residual, squared.
TEST(MotionResidualGram, SquaredNormAndGradientMatchTheFactoredWeight) {
  for (unsigned seed = 1; seed <= 10; ++seed) {
    const RandomMotion m = MakeMotion(2 + seed % 4, seed % 2 ? std::vector<int>{2} : std::vector<int>{}, seed);
    const SymmetricMatrix h(m.W.transpose() * m.W);
    const MotionResidual gram(m.R0, m.sim, m.x0, MotionWeight::OfGram(h), m.newton, m.kappa0, m.intrinsic_sizes);
    const std::unique_ptr<MotionResidual> factored = MakeResidual(m, true);
    std::vector<const double*> poses, intrinsics;
    for (int k = 0; k < m.n; ++k) poses.push_back(m.blocks[k].data());
    for (size_t c = 0; c < m.intrinsic_sizes.size(); ++c) intrinsics.push_back(m.blocks[m.n + 1 + c].data());
    const double* sim = m.blocks[m.n].data();
    const double expected = ResidualByFormula(m, m.blocks).squaredNorm();
    EXPECT_NEAR(gram.SquaredNorm(poses, sim, intrinsics), expected, 1e-10 * expected) << "seed " << seed;
    EXPECT_NEAR(factored->SquaredNorm(poses, sim, intrinsics), expected, 1e-10 * expected) << "seed " << seed;
    const Eigen::VectorXd dx = gram.Deviation(poses, sim, intrinsics);
    const Eigen::VectorXd g = m.W.transpose() * (m.W * (dx - m.newton));
    EXPECT_LT((gram.DeviationGradient(dx) - g).norm(), 1e-10 * g.norm()) << "seed " << seed;
    EXPECT_LT((factored->DeviationGradient(dx) - g).norm(), 1e-10 * g.norm()) << "seed " << seed;
    EXPECT_THROW(gram.Evaluate(poses, sim, intrinsics), std::logic_error);
  }
}

}  // namespace
}  // namespace pgba
