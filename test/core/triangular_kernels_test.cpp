#include <Eigen/SparseCholesky>
#include <gtest/gtest.h>

#include "cloth_sim/core/local_step.h"
#include "cloth_sim/core/triangular_kernels.h"
#include "test_util.h"

namespace cloth_sim {
namespace {

TEST(TriangularKernels, FusedSolveMatchesALibrarySolveForAllThreeColumns) {
  // Large enough for every code path: remainder loops, long columns near the root.
  const Eigen::SparseMatrix<double> a = test::gridSystemMatrix(23, 17, 1.0 / 30.0);
  CholmodFactor factor;
  ASSERT_TRUE(factor.compute(a));
  const LowerFactor f = factor.exportLower();
  const Eigen::MatrixX3d b = Eigen::MatrixX3d::Random(a.rows(), 3);
  const Eigen::MatrixX3d expected = Eigen::SimplicialLLT<Eigen::SparseMatrix<double>>(a).solve(b);

  NodeBuffer x(kNodeStride * f.size, 0.0);  // in the factor's order, pad slots 0
  for (int k = 0; k < f.size; ++k)
    for (int c = 0; c < 3; ++c) x[kNodeStride * k + c] = b(f.permutation[k], c);
  solveFused3(f, x.data());
  double error = 0.0;
  for (int k = 0; k < f.size; ++k) {
    for (int c = 0; c < 3; ++c) error += std::pow(x[kNodeStride * k + c] - expected(f.permutation[k], c), 2);
    EXPECT_EQ(x[kNodeStride * k + 3], 0.0);  // the pad slot stays 0
  }
  EXPECT_LT(std::sqrt(error), 1e-12 * expected.norm());
}

TEST(TriangularKernels, ForwardAndBackwardAreTheTwoTriangularSolves) {
  const Eigen::SparseMatrix<double> a = test::gridSystemMatrix(6, 5, 1.0 / 60.0);
  CholmodFactor factor;
  ASSERT_TRUE(factor.compute(a));
  const LowerFactor f = factor.exportLower();
  Eigen::MatrixXd l = Eigen::MatrixXd::Zero(f.size, f.size);
  for (int j = 0; j < f.size; ++j) {
    l(j, j) = 1.0 / f.inv_diagonal[j];
    for (int k = f.col_start[j]; k < f.col_start[j + 1]; ++k) l(f.col_row[k], j) = f.col_value[k];
  }
  const Eigen::MatrixX3d b = Eigen::MatrixX3d::Random(f.size, 3);
  NodeBuffer x(kNodeStride * f.size, 0.0);
  for (int k = 0; k < f.size; ++k)
    for (int c = 0; c < 3; ++c) x[kNodeStride * k + c] = b(k, c);
  forwardSolve3(f, x.data());
  const Eigen::MatrixX3d z = l.triangularView<Eigen::Lower>().solve(b);
  for (int k = 0; k < f.size; ++k)
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(x[kNodeStride * k + c], z(k, c), 1e-12 * z.norm());
  backwardSolve3(f, x.data());
  const Eigen::MatrixX3d y = l.transpose().triangularView<Eigen::Upper>().solve(z);
  for (int k = 0; k < f.size; ++k)
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(x[kNodeStride * k + c], y(k, c), 1e-12 * y.norm());
}

}  // namespace
}  // namespace cloth_sim
