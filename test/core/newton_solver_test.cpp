#include <cmath>

#include <gtest/gtest.h>

#include "cloth_sim/core/implicit_euler.h"
#include "cloth_sim/core/newton_solver.h"
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
  g.model.time_step = 1.0 / 30.0;
  PinSet pins;
  // Every spring starts at 40 % of its rest length plus noise: compression everywhere.
  State s = State::atRest(0.4 * g.rest_positions + 0.01 * Points::Random(3, 36));
  const ImplicitStepProblem problem = ImplicitStepProblem::build(g.model, pins, s);
  NewtonSolver solver;
  const SolveResult r = solver.step({g.model, pins, 1}, test::convergedSettings(200, 1e-13), s);
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

TEST(Newton, ConservesLinearMomentumWithoutExternalForces) {
  NewtonSolver solver;
  // Round-off only: 1e-9 of the momentum magnitude sum_i m_i |v_i|.
  EXPECT_LT(test::momentumDrift(solver, test::convergedSettings(1000, 1e-14), 20), 1e-9);
}

}  // namespace
}  // namespace cloth_sim
