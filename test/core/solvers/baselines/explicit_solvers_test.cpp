#include <cmath>

#include <gtest/gtest.h>

#include "cloth_sim/core/solvers/baselines/explicit_solvers.h"
#include "cloth_sim/core/model/spring_kernels.h"
#include "test_util.h"

namespace cloth_sim {
namespace {

Model oneParticle() {
  Model m;
  m.mass = Eigen::VectorXd::Constant(1, 0.3);
  return m;
}

TEST(ExplicitEuler, FreeFallMatchesTheSymplecticEulerSum) {
  const double h = 0.01;
  const Model m = oneParticle();
  PinSet pins;
  State s = State::atRest(Points::Zero(3, 1));
  ExplicitEulerSolver solver;
  const int n = 100;
  for (int k = 0; k < n; ++k) solver.step({m, pins, h, 1}, SolverSettings{}, s);
  // v_n = n h g, x_n = h^2 g n (n + 1) / 2.
  EXPECT_NEAR(s.velocities(2, 0), n * h * -9.81, 1e-12);
  EXPECT_NEAR(s.positions(2, 0), h * h * -9.81 * n * (n + 1) / 2.0, 1e-12);
  EXPECT_NEAR(s.time, n * h, 1e-12);
}

TEST(Verlet, FreeFallIsExact) {
  const double h = 0.01;
  const Model m = oneParticle();
  PinSet pins;
  State s = State::atRest(Points::Zero(3, 1));
  VerletSolver solver;
  for (int k = 0; k < 100; ++k) solver.step({m, pins, h, 1}, SolverSettings{}, s);
  EXPECT_NEAR(s.positions(2, 0), 0.5 * -9.81 * 1.0, 1e-12);
  EXPECT_NEAR(s.velocities(2, 0), -9.81, 1e-12);
}

/// Oscillator: particle 1 of mass m on a spring k hard-pinned at the origin, no gravity.
struct Oscillator {
  test::HangingSpring sys;
  State state;
  double omega;
  Oscillator(double h_times_omega, double amplitude) : sys(test::makeHangingSpring(0.5, 200.0, 1.0, 1.0)) {
    omega = std::sqrt(200.0 / 0.5);
    sys.h = h_times_omega / omega;
    sys.model.gravity.setZero();
    state = State::atRest(sys.rest);
    state.positions(2, 1) -= amplitude;  // stretched
  }
  double energy() const {
    return 0.5 * 0.5 * state.velocities.col(1).squaredNorm() + springEnergy(sys.model.springs, state.positions);
  }
  double displacement() const { return std::abs(state.positions(2, 1) + 1.0); }
};

template <typename SolverT>
void expectBoundedEnergy(double h_times_omega, double tolerance) {
  Oscillator osc(h_times_omega, 0.1);
  SolverT solver;
  const double e0 = osc.energy();
  const int steps = static_cast<int>(10 * 2 * M_PI / h_times_omega);  // ten periods
  double worst = 0.0;
  for (int k = 0; k < steps; ++k) {
    solver.step({osc.sys.model, osc.sys.pins, osc.sys.h, 1}, SolverSettings{}, osc.state);
    worst = std::max(worst, std::abs(osc.energy() - e0) / e0);
  }
  EXPECT_LT(worst, tolerance) << SolverT().name();
}

TEST(ExplicitSolvers, EnergyStaysBoundedBelowTheStabilityLimit) {
  // Symplectic schemes: no drift, an O(h omega) (Euler) or O((h omega)^2) (Verlet) wobble.
  expectBoundedEnergy<ExplicitEulerSolver>(2 * M_PI / 200, 0.04);
  expectBoundedEnergy<VerletSolver>(2 * M_PI / 200, 3e-4);
}

template <typename SolverT>
double amplitudeAfter(double h_times_omega, int steps) {
  Oscillator osc(h_times_omega, 0.01);
  SolverT solver;
  double worst = 0.0;
  for (int k = 0; k < steps; ++k) {
    solver.step({osc.sys.model, osc.sys.pins, osc.sys.h, 1}, SolverSettings{}, osc.state);
    worst = std::max(worst, osc.displacement());
  }
  return worst;
}

TEST(ExplicitSolvers, StabilityLimitIsHOmegaEqualsTwo) {
  // h omega = 1.9: bounded (at most 1/sqrt(1 - 0.95^2) ~ 3.2 times the start amplitude).
  EXPECT_LT(amplitudeAfter<ExplicitEulerSolver>(1.9, 400), 0.05);
  EXPECT_LT(amplitudeAfter<VerletSolver>(1.9, 400), 0.05);
  // h omega = 2.2: the amplitude grows geometrically.
  EXPECT_GT(amplitudeAfter<ExplicitEulerSolver>(2.2, 100), 1e3);
  EXPECT_GT(amplitudeAfter<VerletSolver>(2.2, 100), 1e3);
}

TEST(ExplicitSolvers, HardPinFollowsItsTarget) {
  test::HangingSpring sys = test::makeHangingSpring(0.1, 50.0, 0.5, 0.005);
  State s = State::atRest(sys.rest);
  ExplicitEulerSolver solver;
  const int id = sys.pins.pins()[0].id;
  sys.pins.moveTarget(id, Vec3(0.01, 0.0, 0.0));
  solver.step({sys.model, sys.pins, sys.h, 1}, SolverSettings{}, s);
  EXPECT_EQ(s.positions.col(0), Vec3(0.01, 0.0, 0.0));
  EXPECT_NEAR(s.velocities(0, 0), 0.01 / 0.005, 1e-12);
}

}  // namespace
}  // namespace cloth_sim
