#include <cmath>

#include <gtest/gtest.h>

#include "cloth_sim/core/solvers/implicit_euler_problem.h"
#include "cloth_sim/core/solvers/local_global/local_global_solver.h"
#include "cloth_sim/core/solvers/newton_solver.h"
#include "test_util.h"

namespace cloth_sim {
namespace {

TEST(Newton, HangingMassSettlesAtStaticStretchMgOverK) {
  NewtonSolver solver;
  EXPECT_LT(test::staticStretchError(solver, test::convergedSettings(100, 1e-14)), 1e-6);
}

TEST(Newton, SoftPinSagsByWeightOverPinStiffness) {
  NewtonSolver solver;
  EXPECT_LT(test::softPinSagError(solver, test::convergedSettings(50)), 1e-6);
}

TEST(Newton, ConvergesFromACrumpledStartWhereTheHessianIsIndefinite) {
  BuiltObject g = test::makeGrid(6, 6, 500.0, 50.0, 5.0);
  const double h = 1.0 / 30.0;
  PinSet pins;
  // Every spring starts at 40 % of its rest length plus noise: compression everywhere.
  State s = State::atRest(0.4 * g.rest_positions + 0.01 * Points::Random(3, 36));
  const ImplicitStepProblem problem = ImplicitStepProblem::build(g.model, pins, s, h);
  NewtonSolver solver;
  const SolveResult r = solver.step({g.model, pins, h, 1}, test::convergedSettings(200, 1e-13), s);
  EXPECT_TRUE(r.converged);
  Points grad;
  problem.gradient(s.positions, grad);
  Points grad0;
  problem.gradient(problem.inertial, grad0);
  EXPECT_LT(grad.norm(), 1e-9 * grad0.norm());
  // And it is a minimum: nearby points are not lower.
  const double g_star = problem.objective(s.positions);
  for (int trial = 0; trial < 10; ++trial) {
    EXPECT_GE(problem.objective(s.positions + 1e-4 * Points::Random(3, 36)), g_star);
  }
}

TEST(Newton, WarmStartReachesTheSameMinimumInFewerIterations) {
  BuiltObject g = test::makeGrid(8, 8, 400.0, 40.0, 4.0);
  const double h = 1.0 / 30.0;
  PinSet pins;
  pins.add(0, g.rest_positions.col(0), 0.0, 64);
  State s = State::atRest(g.rest_positions);
  s.velocities.row(2).setConstant(-1.0);
  s.velocities.col(0).setZero();
  const SolverInput input{g.model, pins, h, 1};
  const ImplicitStepProblem problem = ImplicitStepProblem::build(g.model, pins, s, h);
  NewtonSolver cold, warm;
  Points x_cold = problem.inertial;
  const SolveResult r_cold = cold.minimize(input, test::convergedSettings(500, 1e-13), problem, x_cold);
  State guess = s;
  LocalGlobalSolver lg;
  lg.step(input, test::convergedSettings(200, 0.0), guess);
  Points x_warm = guess.positions;
  const SolveResult r_warm = warm.minimize(input, test::convergedSettings(500, 1e-13), problem, x_warm);
  ASSERT_TRUE(r_cold.converged);
  ASSERT_TRUE(r_warm.converged);
  EXPECT_LT(r_warm.iterations, r_cold.iterations);
  EXPECT_LT((x_warm - x_cold).norm(), 1e-10 * (x_cold - problem.inertial).norm());
}

TEST(Newton, EigenAndCholmodFactorizationsAgree) {
  BuiltObject g = test::makeGrid(6, 6, 500.0, 50.0, 5.0);
  PinSet pins;
  pins.add(3, g.rest_positions.col(3), 0.0, 36);
  State a = State::atRest(g.rest_positions), b = a;
  SolverSettings settings = test::convergedSettings(100, 1e-13);
  NewtonSolver na, nb;
  na.step({g.model, pins, 1.0 / 60.0, 1}, settings, a);
  settings.linear_solver = LinearSolver::kEigen;
  nb.step({g.model, pins, 1.0 / 60.0, 1}, settings, b);
  EXPECT_LT((a.positions - b.positions).norm(), 1e-12 * a.positions.norm());
}

TEST(Newton, ConservesLinearMomentumWithoutExternalForces) {
  NewtonSolver solver;
  // Round-off only: 1e-9 of the momentum magnitude sum_i m_i |v_i|.
  EXPECT_LT(test::momentumDrift(solver, test::convergedSettings(1000, 1e-14), 20), 1e-9);
}

}  // namespace
}  // namespace cloth_sim
