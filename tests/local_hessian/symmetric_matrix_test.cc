// SymmetricMatrix: the lower triangle stored once gives back the matrix, its entries and its
// products as the dense symmetric matrix does.
#include "modules/local_hessian/symmetric_matrix.h"

#include <gtest/gtest.h>

namespace pgba {
namespace {

TEST(SymmetricMatrix, KeepsTheLowerTriangleAndMultipliesAsTheDenseMatrix) {
  for (int n : {0, 1, 2, 7, 18, 45}) {
    const Eigen::MatrixXd B = Eigen::MatrixXd::Random(n, n);
    const Eigen::MatrixXd S = B * B.transpose();
    Eigen::MatrixXd lower_only = S;
    lower_only.triangularView<Eigen::StrictlyUpper>().setConstant(1e9);  // never read
    const SymmetricMatrix packed(lower_only);
    ASSERT_EQ(packed.rows(), n);
    Eigen::MatrixXd expected = S;
    expected.triangularView<Eigen::StrictlyUpper>() = S.transpose().triangularView<Eigen::StrictlyUpper>();
    EXPECT_EQ(packed.Dense(), expected) << n;
    for (int r = 0; r < n; ++r)
      for (int c = 0; c < n; ++c) EXPECT_EQ(packed(r, c), expected(r, c));
    const Eigen::VectorXd x = Eigen::VectorXd::Random(n);
    EXPECT_LE((packed * x - expected * x).norm(), 1e-12 * (1.0 + (expected * x).norm())) << n;
    if (n > 0) EXPECT_EQ(packed.MaxDiagonal(), expected.diagonal().maxCoeff());
    EXPECT_TRUE(packed.allFinite());
    EXPECT_TRUE(packed == SymmetricMatrix(expected));
  }
}

}  // namespace
}  // namespace pgba
