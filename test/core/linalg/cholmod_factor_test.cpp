#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "cloth_sim/core/linalg/cholmod_factor.h"
#include "test_util.h"

namespace cloth_sim {
namespace {

TEST(CholmodFactor, ExportedFactorReproducesThePermutedMatrix) {
  const Eigen::SparseMatrix<double> a = test::gridSystemMatrix(9, 7, 1.0 / 30.0);
  CholmodFactor factor;
  ASSERT_TRUE(factor.compute(a));
  const LowerFactor f = factor.exportLower();
  ASSERT_EQ(f.size, a.rows());
  const Eigen::MatrixXd l = test::denseLower(f);
  const Eigen::MatrixXd dense = Eigen::MatrixXd(a);
  Eigen::MatrixXd permuted(f.size, f.size);
  for (int r = 0; r < f.size; ++r)
    for (int c = 0; c < f.size; ++c) permuted(r, c) = dense(f.permutation[r], f.permutation[c]);
  EXPECT_LT((l * l.transpose() - permuted).norm(), 1e-13 * dense.norm());
  for (int j = 0; j < f.size; ++j) {  // rows strictly below the diagonal, increasing
    for (int k = f.col_start[j]; k < f.col_start[j + 1]; ++k) {
      EXPECT_GT(f.col_row[k], k == f.col_start[j] ? j : f.col_row[k - 1]);
    }
  }
  EXPECT_EQ(static_cast<double>(f.offDiagonalCount() + f.size), factor.factorNonZeros());
}

TEST(CholmodFactor, SolvesThreeColumnsLikeADenseSolve) {
  const Eigen::SparseMatrix<double> a = test::gridSystemMatrix(12, 10, 1.0 / 60.0);
  for (auto kind : {CholmodFactor::Kind::kSimplicial, CholmodFactor::Kind::kSupernodal}) {
    CholmodFactor factor(kind);
    ASSERT_TRUE(factor.compute(a));
    const Eigen::MatrixX3d b = Eigen::MatrixX3d::Random(a.rows(), 3);
    Eigen::MatrixX3d x = b;
    factor.solveInPlace(x.data(), 3);
    const Eigen::MatrixX3d expected = Eigen::MatrixXd(a).llt().solve(b);
    EXPECT_LT((x - expected).norm(), 1e-12 * expected.norm());
  }
}

TEST(CholmodFactor, ReportsAMatrixThatIsNotPositiveDefinite) {
  Eigen::SparseMatrix<double> a = test::gridSystemMatrix(5, 5, 1.0 / 60.0);
  CholmodFactor factor(CholmodFactor::Kind::kSupernodal);
  ASSERT_TRUE(factor.compute(a));
  a.coeffRef(7, 7) = -1.0;
  EXPECT_FALSE(factor.factorize(a));
  EXPECT_THROW(factor.exportLower(), std::logic_error);
}

}  // namespace
}  // namespace cloth_sim
