#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>
#include <gtest/gtest.h>

#include "cloth_sim/core/io/scene.h"
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

/// Positions after @p frames frames of the hanging scene at 24 x 24 with @p linear.
Points hangingWith(LinearSolver linear, const std::string& solver, int substeps, int iterations,
                   double tolerance, int frames) {
  SceneOverrides o;
  o.resolution = 24;
  o.solver = solver;
  o.substeps = substeps;
  o.iterations = iterations;
  o.tolerance = tolerance;
  o.linear_solver = linear;
  Simulation sim = makeSimulation(
      applyOverrides(loadSceneFile(test::sourcePath("config/scenes/hanging.yaml")), o));
  for (int f = 0; f < frames; ++f) EXPECT_EQ(sim.step().status, StepStatus::kOk);
  return sim.state().positions;
}

TEST(GlobalSystem, FloatFactorReachesTheDoublePathsFixedPointInTheSimulation) {
  // Each step iterated to a relative change of about 1e-11 (plain) or 1e-12 (Anderson, which
  // stalls near there): the float factor's iterates end where the double factor's do (the
  // residual is exact). Measured: 2.5e-12 m and 2.8e-12 m apart on the 1.4 m diagonal.
  const std::pair<std::string, std::pair<int, double>> configs[] = {
      {"local_global", {3000, 1e-11}}, {"anderson", {500, 1e-12}}};
  for (const auto& [solver, budget] : configs) {
    const Points d = hangingWith(LinearSolver::kFused, solver, 4, budget.first, budget.second, 1);
    const Points f = hangingWith(LinearSolver::kFusedFloat, solver, 4, budget.first, budget.second, 1);
    EXPECT_LT((f - d).cwiseAbs().maxCoeff(), 1e-10) << solver;  // m
  }
  // At the scene's budget (32 substeps of 3 iterations) they differ, but by far less than the
  // iteration error.
  const Points d = hangingWith(LinearSolver::kFused, "local_global", 32, 3, 0.0, 5);
  const Points f = hangingWith(LinearSolver::kFusedFloat, "local_global", 32, 3, 0.0, 5);
  EXPECT_GT((f - d).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_LT((f - d).cwiseAbs().maxCoeff(), 1e-5);
}

TEST(GlobalSystem, LinearSolverNamesRoundTrip) {
  for (LinearSolver s : kLinearSolvers) {
    EXPECT_EQ(linearSolverFromName(linearSolverName(s)), s);
  }
  EXPECT_THROW(linearSolverFromName("umfpack"), std::invalid_argument);
}

}  // namespace
}  // namespace cloth_sim
