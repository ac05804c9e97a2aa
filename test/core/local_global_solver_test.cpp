#include <cmath>

#include <gtest/gtest.h>

#include "cloth_sim/core/implicit_euler.h"
#include "cloth_sim/core/local_global_solver.h"
#include "cloth_sim/core/newton_solver.h"
#include "test_util.h"

namespace cloth_sim {
namespace {

TEST(LocalGlobal, HangingMassSettlesAtStaticStretchMgOverK) {
  const double m = 0.2, k = 50.0, rest = 0.5;
  test::HangingSpring sys = test::makeHangingSpring(m, k, rest, 1.0 / 60.0);
  sys.model.damping = 5.0;
  State s = State::atRest(sys.rest);
  LocalGlobalSolver solver;
  for (int step = 0; step < 1200; ++step) {
    solver.step({sys.model, sys.pins, 1}, test::convergedSettings(), s);
  }
  const double stretch = (s.positions.col(1) - s.positions.col(0)).norm() - rest;
  const double expected = m * 9.81 / k;
  EXPECT_LT(std::abs(stretch - expected) / expected, 1e-6) << stretch << " vs " << expected;
}

TEST(LocalGlobal, SoftPinSagsByWeightOverPinStiffness) {
  Model model;
  model.mass = Eigen::VectorXd::Constant(1, 0.4);
  model.damping = 5.0;
  PinSet pins;
  pins.add(0, Vec3(0, 0, 1), 80.0, 1);
  State s = State::atRest(Points(Vec3(0, 0, 1)));
  LocalGlobalSolver solver;
  for (int step = 0; step < 1200; ++step) solver.step({model, pins, 1}, test::convergedSettings(), s);
  EXPECT_LT(std::abs((1.0 - s.positions(2, 0)) - 0.4 * 9.81 / 80.0) / (0.4 * 9.81 / 80.0), 1e-6);
}

/// A moving 6 x 6 cloth with a hard and a soft pin, a few steps into a swing.
struct SwingingCloth {
  BuiltObject g = test::makeGrid(6, 6, 200.0, 20.0, 2.0);
  PinSet pins;
  State state;
  SwingingCloth() {
    g.model.time_step = 1.0 / 60.0;
    pins.add(0, g.rest_positions.col(0), 0.0, 36);
    pins.add(5, g.rest_positions.col(5), 150.0, 36);
    state = State::atRest(g.rest_positions);
    LocalGlobalSolver warmup;
    for (int k = 0; k < 15; ++k) warmup.step({g.model, pins, 1}, SolverSettings{}, state);
  }
  SolverInput input() const { return {g.model, pins, 1}; }
};

Points newtonSolution(const SwingingCloth& c) {
  State s = c.state;
  NewtonSolver newton;
  EXPECT_TRUE(newton.step(c.input(), test::convergedSettings(1000, 1e-14), s).converged);
  return s.positions;
}

TEST(LocalGlobal, ConvergesToNewtonsSolutionOfTheSameStep) {
  SwingingCloth c;
  const Points x_star = newtonSolution(c);
  const Points y = ImplicitStepProblem::build(c.g.model, c.pins, c.state).inertial;
  State s = c.state;
  LocalGlobalSolver lg;
  const SolveResult r = lg.step(c.input(), test::convergedSettings(100000, 1e-14), s);
  EXPECT_TRUE(r.converged);
  const double relative_error = (s.positions - x_star).norm() / (y - x_star).norm();
  EXPECT_LT(relative_error, 1e-8) << "after " << r.iterations << " iterations";
}

TEST(LocalGlobal, ObjectiveNeverIncreasesAcrossIterations) {
  SwingingCloth c;
  // Squash the start so many springs are compressed: the interesting case for monotonicity.
  c.state.positions = 0.7 * c.state.positions;
  c.pins.moveTarget(0, c.state.positions.col(0));
  std::vector<double> trace;
  LocalGlobalSolver lg;
  lg.setObjectiveTrace(&trace);
  State s = c.state;
  lg.step(c.input(), test::convergedSettings(300, 0.0), s);
  ASSERT_EQ(trace.size(), 301u);
  for (std::size_t k = 1; k < trace.size(); ++k) {
    EXPECT_LE(trace[k], trace[k - 1] + 1e-12 * std::abs(trace[k - 1])) << "iteration " << k;
  }
  EXPECT_LT(trace.back(), trace.front());
}

TEST(LocalGlobal, ConservesLinearMomentumAtEveryIterationCount) {
  BuiltObject g = test::makeGrid(5, 5, 300.0, 30.0, 3.0);
  g.model.gravity.setZero();
  PinSet pins;
  State s = State::atRest(g.rest_positions);
  s.velocities = Points::Random(3, 25);
  const Vec3 p0 = s.velocities * g.model.mass;
  LocalGlobalSolver solver;
  SolverSettings few;
  few.max_iterations = 3;  // not converged: each global solve conserves momentum on its own
  for (int step = 0; step < 50; ++step) solver.step({g.model, pins, 1}, few, s);
  // Round-off only: bounded by 1e-9 of the momentum magnitude sum_i m_i |v_i|.
  const double scale = s.velocities.colwise().norm().dot(g.model.mass);
  EXPECT_LT((s.velocities * g.model.mass - p0).norm(), 1e-9 * scale);
}

TEST(LocalGlobal, FactorKeptAcrossStepsAndTargetMoves) {
  SwingingCloth c;
  LocalGlobalSolver lg;
  State s = c.state;
  for (int k = 0; k < 30; ++k) {
    c.pins.moveTarget(c.pins.pins()[0].id, c.g.rest_positions.col(0) + Vec3(0.01 * k, 0, 0));
    lg.step({c.g.model, c.pins, 7}, SolverSettings{}, s);
  }
  EXPECT_EQ(lg.factorizationCount(), 1);
  lg.step({c.g.model, c.pins, 8}, SolverSettings{}, s);  // a new revision: refactor once
  lg.step({c.g.model, c.pins, 8}, SolverSettings{}, s);
  EXPECT_EQ(lg.factorizationCount(), 2);
}

TEST(Chebyshev, ConvergesToNewtonsSolution) {
  SwingingCloth c;
  const Points x_star = newtonSolution(c);
  const Points y = ImplicitStepProblem::build(c.g.model, c.pins, c.state).inertial;
  State s = c.state;
  ChebyshevSolver cheb;
  cheb.step(c.input(), SolverSettings{}, s);  // measures rho
  s = c.state;
  const SolveResult r = cheb.step(c.input(), test::convergedSettings(100000, 1e-14), s);
  EXPECT_TRUE(r.converged);
  EXPECT_LT((s.positions - x_star).norm() / (y - x_star).norm(), 1e-8);
}

TEST(Chebyshev, NeverWorseThanPlainLocalGlobalAndMonotone) {
  SwingingCloth c;
  c.g.model.setFamilyStiffness(SpringFamily::kStructural, 5000.0);  // slow plain convergence
  ChebyshevSolver cheb;
  LocalGlobalSolver plain;
  std::vector<double> cheb_trace, plain_trace;
  cheb.setObjectiveTrace(&cheb_trace);
  plain.setObjectiveTrace(&plain_trace);
  State warm = c.state;
  cheb.step(c.input(), SolverSettings{}, warm);  // first step measures rho
  EXPECT_GT(cheb.rho(), 0.5);
  EXPECT_LT(cheb.rho(), 1.0);
  for (int iterations : {1, 2, 3, 5, 10, 20, 50, 100}) {
    State a = c.state, b = c.state;
    cheb.step(c.input(), test::convergedSettings(iterations, 0.0), a);
    plain.step(c.input(), test::convergedSettings(iterations, 0.0), b);
    EXPECT_LE(cheb_trace.back(), plain_trace.back() + 1e-12 * std::abs(plain_trace.back()))
        << iterations << " iterations";
    for (std::size_t k = 1; k < cheb_trace.size(); ++k) {
      EXPECT_LE(cheb_trace[k], cheb_trace[k - 1] + 1e-12 * std::abs(cheb_trace[k - 1]));
    }
  }
}

}  // namespace
}  // namespace cloth_sim
