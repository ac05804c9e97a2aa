#include <cmath>

#include <gtest/gtest.h>

#include "cloth_sim/core/implicit_euler.h"
#include "cloth_sim/core/newton_solver.h"
#include "test_util.h"

namespace cloth_sim {
namespace {

TEST(Newton, HangingMassSettlesAtStaticStretchMgOverK) {
  const double m = 0.2, k = 50.0, rest = 0.5;
  test::HangingSpring sys = test::makeHangingSpring(m, k, rest, 1.0 / 60.0);
  sys.model.damping = 5.0;
  State s = State::atRest(sys.rest);
  NewtonSolver solver;
  const SolverSettings settings = test::convergedSettings(100, 1e-14);
  for (int step = 0; step < 1200; ++step) solver.step({sys.model, sys.pins, 1}, settings, s);
  const double stretch = (s.positions.col(1) - s.positions.col(0)).norm() - rest;
  const double expected = m * 9.81 / k;
  EXPECT_LT(std::abs(stretch - expected) / expected, 1e-6) << stretch << " vs " << expected;
}

TEST(Newton, SoftPinSagsByWeightOverPinStiffness) {
  Model model;
  model.mass = Eigen::VectorXd::Constant(1, 0.4);
  model.damping = 5.0;
  PinSet pins;
  const double k_pin = 80.0;
  pins.add(0, Vec3(0, 0, 1), k_pin, 1);
  State s = State::atRest(Points(Vec3(0, 0, 1)));
  NewtonSolver solver;
  for (int step = 0; step < 1200; ++step) solver.step({model, pins, 1}, test::convergedSettings(50), s);
  EXPECT_LT(std::abs((1.0 - s.positions(2, 0)) - 0.4 * 9.81 / k_pin) / (0.4 * 9.81 / k_pin), 1e-6);
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
  BuiltObject g = test::makeGrid(5, 5, 300.0, 30.0, 3.0);
  g.model.gravity.setZero();
  PinSet pins;
  State s = State::atRest(g.rest_positions);
  s.velocities = Points::Random(3, 25);
  const Vec3 p0 = s.velocities * g.model.mass;
  NewtonSolver solver;
  for (int step = 0; step < 20; ++step) {
    solver.step({g.model, pins, 1}, test::convergedSettings(1000, 1e-14), s);
  }
  const double scale = s.velocities.colwise().norm().dot(g.model.mass);
  EXPECT_LT((s.velocities * g.model.mass - p0).norm(), 1e-9 * scale);
}

}  // namespace
}  // namespace cloth_sim
