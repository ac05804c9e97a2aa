#include <cmath>

#include <gtest/gtest.h>

#include "cloth_sim/core/solvers/implicit_euler_problem.h"
#include "test_util.h"

namespace cloth_sim {
namespace {

TEST(ImplicitEuler, InertialPredictionWithDampingAndHardPins) {
  BuiltObject g = test::makeGrid(3, 3, 100.0, 0.0, 0.0);
  g.model.damping = 2.0;
  const double h = 0.01;
  PinSet pins;
  pins.add(4, Vec3(9, 9, 9), 0.0, 9);
  State s = State::atRest(g.rest_positions);
  s.velocities = Points::Random(3, 9);
  const ImplicitStepProblem p = ImplicitStepProblem::build(g.model, pins, s, h);
  EXPECT_NEAR(velocityDecay(g.model, h), std::exp(-0.02), 1e-15);
  EXPECT_NEAR((p.inertial.col(0) - (s.positions.col(0) + 0.01 * std::exp(-0.02) * s.velocities.col(0))).norm(),
              0.0, 1e-15);
  EXPECT_EQ(p.inertial.col(4), Vec3(9, 9, 9));
}

TEST(ImplicitEuler, GradientMatchesFiniteDifferences) {
  BuiltObject g = test::makeGrid(3, 4, 200.0, 20.0, 2.0);
  PinSet pins;
  pins.add(0, Vec3(0.1, 0.2, 1.3), 0.0, 12);    // hard
  pins.add(5, Vec3(0.0, 0.0, 0.8), 75.0, 12);   // soft
  State s = State::atRest(g.rest_positions);
  s.velocities = 0.3 * Points::Random(3, 12);
  const ImplicitStepProblem p = ImplicitStepProblem::build(g.model, pins, s, 1.0 / 30.0);
  Points x = p.inertial + 0.02 * Points::Random(3, 12);
  x.col(0) = pins.pins()[0].target;
  Points grad;
  p.gradient(x, grad);
  EXPECT_EQ(grad.col(0).norm(), 0.0);  // hard-pinned: not an unknown
  const double eps = 1e-6;
  for (int i = 1; i < 12; ++i) {
    for (int a = 0; a < 3; ++a) {
      Points xp = x, xm = x;
      xp(a, i) += eps;
      xm(a, i) -= eps;
      const double numeric = (p.objective(xp) - p.objective(xm)) / (2 * eps);
      EXPECT_NEAR(grad(a, i), numeric, 1e-7 * (1.0 + std::abs(numeric)));
    }
  }
}

TEST(ImplicitEuler, FinishGivesBackwardDifferenceVelocity) {
  BuiltObject g = test::makeGrid(2, 2, 10.0, 0.0, 0.0);
  PinSet pins;
  State s = State::atRest(g.rest_positions);
  s.time = 2.0;
  const double h = 1.0 / 60.0;
  const ImplicitStepProblem p = ImplicitStepProblem::build(g.model, pins, s, h);
  const Points x = s.positions + Points::Constant(3, 4, 0.5);
  const State next = p.finish(x, s.time);
  EXPECT_NEAR((next.velocities - Points::Constant(3, 4, 0.5 / h)).norm(), 0.0, 1e-12);
  EXPECT_DOUBLE_EQ(next.time, 2.0 + h);
}

}  // namespace
}  // namespace cloth_sim
