#include <algorithm>
#include <cmath>

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>
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

TEST(GlobalSystem, FloatFactorCorrectionsReachTheDoubleSolution) {
  // x_{k+1} = x_k + A_f^-1 (b - A x_k): the residual in double, the solve in float. One step is
  // float-accurate; the fixed point is the double solution (to double round-off).
  const Eigen::SparseMatrix<double> a = test::gridSystemMatrix(30, 30, 1.0 / 30.0);
  const int n = static_cast<int>(a.rows());
  const Eigen::MatrixX3d b = Eigen::MatrixX3d::Random(n, 3);
  const Eigen::MatrixX3d expected = Eigen::SimplicialLLT<Eigen::SparseMatrix<double>>(a).solve(b);
  GlobalSystem system;
  system.factor(a, LinearSolver::kFusedFloat);
  EXPECT_FALSE(system.supernodalFloat().values.empty());
  NodeBuffer rhs(kNodeStride * n, 0.0), x(rhs.size(), 0.0), next(rhs.size());
  for (int k = 0; k < n; ++k)
    for (int c = 0; c < 3; ++c) rhs[kNodeStride * k + c] = b(system.order()[k], c);
  auto error = [&](const NodeBuffer& v) {
    double sum = 0.0;
    for (int k = 0; k < n; ++k)
      for (int c = 0; c < 3; ++c) sum += std::pow(v[kNodeStride * k + c] - expected(system.order()[k], c), 2);
    return std::sqrt(sum) / expected.norm();
  };
  std::vector<double> errors;
  for (int k = 0; k < 12; ++k) {
    next = rhs;
    system.globalStep(x.data(), next.data());
    x.swap(next);
    errors.push_back(error(x));
  }
  EXPECT_LT(errors[0], 1e-5);
  EXPECT_GT(errors[0], 1e-12);   // one float solve is not double-accurate
  EXPECT_LT(errors[1], 0.1 * errors[0]);  // each correction gains float's digits
  // To the double solution: as close as the double backends agree (the first test).
  EXPECT_LT(errors.back(), 1e-12);
  for (int threads : {2, 3}) {  // the same iterates on any threads
    system.setThreads(threads);
    NodeBuffer y(rhs.size(), 0.0);
    for (int k = 0; k < 12; ++k) {
      next = rhs;
      system.globalStep(y.data(), next.data());
      y.swap(next);
    }
    EXPECT_EQ(y, x) << threads;
  }
}

TEST(GlobalSystem, LinearSolverNamesRoundTrip) {
  for (LinearSolver s : kLinearSolvers) {
    EXPECT_EQ(linearSolverFromName(linearSolverName(s)), s);
  }
  EXPECT_THROW(linearSolverFromName("umfpack"), std::invalid_argument);
}

}  // namespace
}  // namespace cloth_sim
