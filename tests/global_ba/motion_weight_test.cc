// MotionWeight keeps W = diag(d) V factored; every product it offers must equal the one
// of the dense matrix, formed here explicitly (the independent truth), for the factored
// (pointless) and the diagonal (Aver_BA) weights.
#include "modules/global_ba/motion_weight.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>

namespace pgba {
namespace {

void ExpectMatchesDense(const MotionWeight& w, const Eigen::MatrixXd& dense) {
  const int n = static_cast<int>(dense.rows());
  ASSERT_EQ(w.size(), n);
  const Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(n, -1.0, 2.0);
  EXPECT_LT((w.Times(x) - dense * x).norm(), 1e-12 * (dense * x).norm());
  EXPECT_LT((w.TransposeTimes(x) - dense.transpose() * x).norm(), 1e-12 * (dense.transpose() * x).norm());
  const Eigen::MatrixXd X = Eigen::MatrixXd::Constant(6, 2, 0.5) + Eigen::MatrixXd::Identity(6, 2);
  const Eigen::MatrixXd expected = dense.middleCols(6, 6) * X;
  EXPECT_LT((w.ColumnsTimes(6, X) - expected).norm(), 1e-12 * expected.norm());
  EXPECT_LT((w.Gram() - dense.transpose() * dense).norm(), 1e-12 * (dense.transpose() * dense).norm());
}

TEST(MotionWeight, FactoredProductsEqualTheDenseMatrix) {
  const int n = 18;
  const Eigen::MatrixXd V = Eigen::HouseholderQR<Eigen::MatrixXd>(Eigen::MatrixXd::Random(n, n)).householderQ();
  const Eigen::VectorXd d = Eigen::VectorXd::LinSpaced(n, 0.1, 40.0);
  const MotionWeight w(std::make_shared<const Eigen::VectorXd>(d), std::make_shared<const Eigen::MatrixXd>(V));
  ExpectMatchesDense(w, d.asDiagonal() * V);
}

TEST(MotionWeight, DiagonalProductsEqualTheDenseMatrix) {
  const Eigen::VectorXd d = Eigen::VectorXd::LinSpaced(18, 3.0, 0.2);
  const MotionWeight w(std::make_shared<const Eigen::VectorXd>(d), nullptr);
  ExpectMatchesDense(w, d.asDiagonal());
}

TEST(MotionWeight, DenseIsTheGivenMatrix) {
  const Eigen::MatrixXd W = Eigen::MatrixXd::Random(18, 18);
  ExpectMatchesDense(MotionWeight::Dense(W), W);
}

}  // namespace
}  // namespace pgba
