#include <Eigen/Dense>
#include <Eigen/SparseCholesky>
#include <gtest/gtest.h>

#include "cloth_sim/core/solvers/local_global/local_step.h"
#include "cloth_sim/core/linalg/supernodal_solves.h"
#include "test_util.h"

namespace cloth_sim {
namespace {

LowerFactor factorOf(const Eigen::SparseMatrix<double>& a) {
  CholmodFactor factor;
  EXPECT_TRUE(factor.compute(a));
  return factor.exportLower();
}

NodeBuffer toNodes(const Eigen::MatrixX3d& b) {
  NodeBuffer x(kNodeStride * b.rows(), 0.0);
  for (int k = 0; k < b.rows(); ++k)
    for (int c = 0; c < 3; ++c) x[kNodeStride * k + c] = b(k, c);
  return x;
}

double distance(const NodeBuffer& x, const Eigen::MatrixX3d& expected) {
  double sum = 0.0;
  for (int k = 0; k < expected.rows(); ++k) {
    for (int c = 0; c < 3; ++c) sum += std::pow(x[kNodeStride * k + c] - expected(k, c), 2);
    EXPECT_EQ(x[kNodeStride * k + 3], 0.0);  // the pad slot stays 0
  }
  return std::sqrt(sum);
}

TEST(TriangularKernels, SupernodesCoverEveryColumnAndKeepEveryEntry) {
  const LowerFactor l = factorOf(test::gridSystemMatrix(23, 17, 1.0 / 30.0));
  for (int width : {1, 3, kMaxSupernode}) {
    const SupernodalFactor f = makeSupernodal(l, width);
    ASSERT_EQ(f.first_column.front(), 0);
    ASSERT_EQ(f.first_column.back(), l.size);
    std::size_t stored = 0;
    for (int s = 0; s < f.supernodeCount(); ++s) {
      const int w = f.first_column[s + 1] - f.first_column[s];
      ASSERT_GE(w, 1);
      ASSERT_LE(w, width);
      stored += w * (w - 1) / 2 + static_cast<std::size_t>(w) * (f.row_start[s + 1] - f.row_start[s]);
    }
    EXPECT_EQ(stored, static_cast<std::size_t>(l.offDiagonalCount())) << "width " << width;
    if (width == kMaxSupernode) {
      EXPECT_LT(f.supernodeCount(), 0.6 * l.size);  // columns do group
    }
  }
}

TEST(TriangularKernels, FusedSolveMatchesALibrarySolveForAllThreeColumns) {
  // Large enough for every supernode width and the remainder loops.
  const Eigen::SparseMatrix<double> a = test::gridSystemMatrix(23, 17, 1.0 / 30.0);
  const LowerFactor l = factorOf(a);
  const Eigen::MatrixX3d b = Eigen::MatrixX3d::Random(a.rows(), 3);
  const Eigen::MatrixX3d solution = Eigen::SimplicialLLT<Eigen::SparseMatrix<double>>(a).solve(b);
  Eigen::MatrixX3d permuted_b(a.rows(), 3), expected(a.rows(), 3);
  for (int k = 0; k < l.size; ++k) {
    permuted_b.row(k) = b.row(l.permutation[k]);
    expected.row(k) = solution.row(l.permutation[k]);
  }
  for (int width : {1, 2, 5, kMaxSupernode}) {
    NodeBuffer x = toNodes(permuted_b);
    solveFused3(makeSupernodal(l, width), x.data());
    EXPECT_LT(distance(x, expected), 1e-12 * expected.norm()) << "width " << width;
  }
}

TEST(TriangularKernels, ForwardAndBackwardAreTheTwoTriangularSolves) {
  const LowerFactor l = factorOf(test::gridSystemMatrix(9, 8, 1.0 / 60.0));
  const SupernodalFactor f = makeSupernodal(l);
  const Eigen::MatrixXd dense = test::denseLower(l);
  const Eigen::MatrixX3d b = Eigen::MatrixX3d::Random(l.size, 3);
  NodeBuffer x = toNodes(b);
  forwardSolve3(f, x.data());
  const Eigen::MatrixX3d z = dense.triangularView<Eigen::Lower>().solve(b);
  EXPECT_LT(distance(x, z), 1e-12 * z.norm());
  backwardSolve3(f, x.data());
  const Eigen::MatrixX3d y = dense.transpose().triangularView<Eigen::Upper>().solve(z);
  EXPECT_LT(distance(x, y), 1e-12 * y.norm());
}

}  // namespace
}  // namespace cloth_sim
