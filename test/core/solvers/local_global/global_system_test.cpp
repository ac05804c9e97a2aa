#include <algorithm>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "cloth_sim/core/solvers/local_global/local_step.h"
#include "cloth_sim/core/solvers/local_global/global_system.h"
#include "test_util.h"

namespace cloth_sim {
namespace {

TEST(GlobalSystem, EveryBackendSolvesTheSameSystem) {
  const Eigen::SparseMatrix<double> a = test::gridSystemMatrix(14, 11, 1.0 / 30.0);
  const int n = static_cast<int>(a.rows());
  const Eigen::MatrixX3d b = Eigen::MatrixX3d::Random(n, 3);
  const Eigen::MatrixX3d expected = Eigen::MatrixXd(a).llt().solve(b);
  for (LinearSolver backend : {LinearSolver::kFused, LinearSolver::kCholmod, LinearSolver::kEigen}) {
    GlobalSystem system;
    system.factor(a, backend);
    EXPECT_EQ(system.backend(), backend);
    std::vector<int> sorted = system.order();
    std::sort(sorted.begin(), sorted.end());
    for (int k = 0; k < n; ++k) ASSERT_EQ(sorted[k], k) << "order() must be a permutation";
    NodeBuffer x(kNodeStride * n, 0.0);
    for (int k = 0; k < n; ++k)
      for (int c = 0; c < 3; ++c) x[kNodeStride * k + c] = b(system.order()[k], c);
    system.solveInPlace(x.data());
    double error = 0.0;
    for (int k = 0; k < n; ++k)
      for (int c = 0; c < 3; ++c) error += std::pow(x[kNodeStride * k + c] - expected(system.order()[k], c), 2);
    EXPECT_LT(std::sqrt(error), 1e-12 * expected.norm()) << linearSolverName(backend);
    EXPECT_GT(system.factorNonZeros(), a.nonZeros() / 2);
  }
}

TEST(GlobalSystem, LinearSolverNamesRoundTrip) {
  for (LinearSolver s : {LinearSolver::kFused, LinearSolver::kCholmod, LinearSolver::kEigen}) {
    EXPECT_EQ(linearSolverFromName(linearSolverName(s)), s);
  }
  EXPECT_THROW(linearSolverFromName("umfpack"), std::invalid_argument);
}

}  // namespace
}  // namespace cloth_sim
