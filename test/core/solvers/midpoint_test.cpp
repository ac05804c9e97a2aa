// Implicit midpoint (Integrator::kImplicitMidpoint): the closed-form rotation of a linear
// oscillator (amplitude and phase), exact damping decay, energy kept by an undamped cloth
// against BDF2, agreement of the solvers, pins following their targets, refusal by the
// explicit solvers. bdf2_test.cpp runs its per-step amplitude, momentum and convergence-order
// tests over every integrator, this one included; midpoint_safeguard_test.cpp tests the energy
// safeguard.
#include <cmath>
#include <cstdio>
#include <string>

#include <gtest/gtest.h>

#include "cloth_sim/core/solvers/baselines/local_global_3n_solver.h"
#include "cloth_sim/core/solvers/implicit_euler_problem.h"
#include "cloth_sim/core/solvers/local_global/local_global_solver.h"
#include "cloth_sim/core/solvers/newton_solver.h"
#include "test_util.h"

namespace cloth_sim {
namespace {

constexpr Integrator kMidpoint = Integrator::kImplicitMidpoint;

SolverSettings settingsFor(Integrator integrator, int iterations = 100, double tolerance = 1e-14) {
  SolverSettings s = test::convergedSettings(iterations, tolerance);
  s.integrator = integrator;
  return s;
}

TEST(ImplicitMidpoint, OscillatorRotatesByTheClosedFormAngleWithConstantEnergy) {
  // On x'' = -w^2 x the step maps (x, v / w) by the Cayley transform of a rotation, a rotation
  // by theta = 2 atan(h w / 2): from x_0 = d, v_0 = 0, exactly x_n = d cos(n theta),
  // v_n = -w d sin(n theta), so 1/2 m v^2 + 1/2 k x^2 is constant. The spring stays along its
  // axis with no gravity: exactly linear.
  const double m = 1.0, k = 100.0, rest = 1.0, omega = std::sqrt(k / m), d = 0.01;
  for (double h_omega : {0.1, 0.5, 2.0}) {
    test::HangingSpring sys = test::makeHangingSpring(m, k, rest, h_omega / omega);
    sys.model.gravity.setZero();
    State s = State::atRest(sys.rest);
    s.positions(2, 1) -= d;
    const double theta = 2.0 * std::atan(0.5 * h_omega);
    NewtonSolver solver;
    double worst_x = 0.0, worst_v = 0.0, worst_energy = 0.0;
    for (int n = 1; n <= 300; ++n) {
      solver.step({sys.model, sys.pins, sys.h, 1}, settingsFor(kMidpoint), s);
      const double x = -s.positions(2, 1) - rest, v = -s.velocities(2, 1);
      worst_x = std::max(worst_x, std::abs(x - d * std::cos(n * theta)));
      worst_v = std::max(worst_v, std::abs(v + omega * d * std::sin(n * theta)));
      const double energy = 0.5 * m * v * v + 0.5 * k * x * x;
      worst_energy = std::max(worst_energy, std::abs(energy - 0.5 * k * d * d));
    }
    std::printf(
        "h omega = %.1f: theta = %.9f (exact %.9f); over 300 steps max |x - d cos n theta| "
        "%.2e m, |v + w d sin n theta| %.2e m/s, energy change %.2e J\n",
        h_omega, theta, h_omega, worst_x, worst_v, worst_energy);
    // Relative 1e-9: round-off of positions near 1 m over 300 steps, not the scheme.
    EXPECT_LT(worst_x, 1e-9 * d);
    EXPECT_LT(worst_v, 1e-9 * omega * d);
    EXPECT_LT(worst_energy, 1e-9 * 0.5 * k * d * d);
  }
}

TEST(ImplicitMidpoint, FreeDampedParticleVelocityDecaysExactlyAsExpMinusGammaT) {
  // v_{n+1} = 4 (x_half - x_n) / h - q v_n with x_half = x_n + (h/2) q v_n: q v_n.
  Model model;
  model.mass = Eigen::VectorXd::Constant(1, 0.3);
  model.gravity.setZero();
  model.damping = 4.0;
  const double h = 0.05;
  PinSet pins;
  State s = State::atRest(Points::Zero(3, 1));
  s.velocities.col(0) = Vec3(1.0, -2.0, 0.5);
  const Vec3 v0 = s.velocities.col(0);
  NewtonSolver solver;
  for (int n = 1; n <= 20; ++n) {
    solver.step({model, pins, h, 1}, settingsFor(kMidpoint), s);
    EXPECT_LT((s.velocities.col(0) - std::exp(-model.damping * n * h) * v0).norm(),
              1e-12)
        << "step " << n;
  }
}

/// The peers' cloth at 8 x 8 (1 m, 1 kg, triangle edges at 1000 N/m, two top corners pinned,
/// undamped) dropped flat, run @p seconds with local_global at 16 substeps of @p iterations
/// per 1/60 s frame (bdf2_test.cpp's configuration); returns its total energy (J).
double energyOfPeerCloth(Integrator integrator, double seconds, int iterations) {
  Simulation sim = test::makePeerCloth8(integrator, iterations);
  const int frames = static_cast<int>(std::lround(seconds * 60.0));
  for (int f = 0; f < frames; ++f) EXPECT_EQ(sim.step().status, StepStatus::kOk);
  return sim.totalEnergy();
}

TEST(ImplicitMidpoint, UndampedClothEnergyDriftsFarLessThanBdf2s) {
  // 10 s of the undamped cloth. BDF2 loses -3.35 J of the 4.96 J the fall releases
  // (bdf2_test.cpp), mostly the springs' vibration; midpoint has no numerical damping.
  const double start = energyOfPeerCloth(kMidpoint, 0.0, 1);
  const double midpoint = energyOfPeerCloth(kMidpoint, 10.0, 1) - start;
  const double bdf2 = energyOfPeerCloth(Integrator::kBdf2, 10.0, 1) - start;
  const double converged = energyOfPeerCloth(kMidpoint, 10.0, 20) - start;
  std::printf(
      "energy drift over 10 s at 16 substeps: implicit_midpoint %+.4f J (1 iteration), "
      "%+.4f J (20 iterations); bdf2 %+.4f J (1 iteration)\n",
      midpoint, converged, bdf2);
  EXPECT_LT(std::abs(midpoint), 0.1 * std::abs(bdf2));
  EXPECT_LT(std::abs(converged), 0.1 * std::abs(bdf2));
}

TEST(ImplicitMidpoint, NewtonLocalGlobalAnd3nAgreeOnAMidpointStep) {
  BuiltObject g = test::makeGrid(6, 6, 400.0, 40.0, 4.0);
  const double h = 1.0 / 60.0;
  g.model.damping = 0.5;
  PinSet pins;
  pins.add(0, g.rest_positions.col(0), 0.0, 36);
  pins.add(5, g.rest_positions.col(5), 30.0, 36);  // a soft pin too
  State s = State::atRest(g.rest_positions);
  NewtonSolver newton;
  const SolverSettings converged = settingsFor(kMidpoint, 100, 1e-14);
  for (int n = 0; n < 5; ++n) newton.step({g.model, pins, h, 1}, converged, s);
  ASSERT_TRUE(ImplicitStepProblem::build(g.model, pins, s, h, kMidpoint).midpoint);

  State by_newton = s, by_local_global = s, by_3n = s;
  newton.step({g.model, pins, h, 1}, converged, by_newton);
  LocalGlobalSolver local_global;
  local_global.step({g.model, pins, h, 1}, settingsFor(kMidpoint, 20000, 1e-15), by_local_global);
  LocalGlobal3nSolver three_n;
  three_n.step({g.model, pins, h, 1}, settingsFor(kMidpoint, 20000, 1e-15), by_3n);
  const double moved = (by_newton.positions - s.positions).norm();
  EXPECT_LT((by_local_global.positions - by_newton.positions).norm(), 1e-9 * moved);
  EXPECT_LT((by_3n.positions - by_newton.positions).norm(), 1e-9 * moved);
  EXPECT_LT((by_local_global.velocities - by_newton.velocities).norm(),
            1e-9 * by_newton.velocities.norm());
  // One matrix, M + (h/2)^2 L, factored once however many steps.
  for (int n = 0; n < 5; ++n) {
    local_global.step({g.model, pins, h, 1}, settingsFor(kMidpoint, 10, 0.0), s);
  }
  EXPECT_EQ(local_global.factorizationCount(), 1);
}

TEST(ImplicitMidpoint, HardPinsEndOnTheirTargetsWithTheMeanVelocity) {
  // Extrapolating x_{n+1} = 2 x_half - x_n would put a pin moved to t at 2 t - x_n.
  BuiltObject g = test::makeGrid(4, 4, 300.0, 30.0, 0.0);
  const double h = 0.01;
  PinSet pins;
  const Vec3 target = g.rest_positions.col(0) + Vec3(0.02, 0.0, 0.01);
  pins.add(0, target, 0.0, 16);
  pins.add(3, g.rest_positions.col(3), 0.0, 16);
  State s = State::atRest(g.rest_positions);
  LocalGlobalSolver solver;
  solver.step({g.model, pins, h, 1}, settingsFor(kMidpoint, 10, 0.0), s);
  EXPECT_EQ(s.positions.col(0), target);
  EXPECT_LT((s.velocities.col(0) - (target - g.rest_positions.col(0)) / h).norm(), 1e-12);
  EXPECT_EQ(s.positions.col(3), g.rest_positions.col(3));
  EXPECT_EQ(s.velocities.col(3), Vec3::Zero());
}

TEST(ImplicitMidpoint, ExplicitSolversRefuseItNamingTheField) {
  for (const char* name : {"explicit_euler", "verlet", "xpbd"}) {
    const auto solver = makeSolver(name);
    EXPECT_FALSE(solver->supports(kMidpoint));
    try {
      requireIntegrator(*solver, kMidpoint);
      ADD_FAILURE() << name << " accepted implicit_midpoint";
    } catch (const std::invalid_argument& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("solver.integrator = implicit_midpoint"), std::string::npos) << what;
    }
  }
  for (const std::string& name : solverNames()) {
    if (name != "explicit_euler" && name != "verlet" && name != "xpbd") {
      EXPECT_TRUE(makeSolver(name)->supports(kMidpoint)) << name;
    }
  }
  EXPECT_EQ(integratorFromName("implicit_midpoint"), kMidpoint);
  EXPECT_STREQ(integratorName(kMidpoint), "implicit_midpoint");
}

}  // namespace
}  // namespace cloth_sim
