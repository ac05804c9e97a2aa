// XPBD, the peers' small-steps baseline: static stretch against m g / k, momentum, what it
// refuses. docs/method.md, "XPBD baseline".
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "cloth_sim/core/solvers/baselines/xpbd_solver.h"
#include "test_util.h"

namespace cloth_sim {
namespace {

SolverSettings sweeps(int n) {
  SolverSettings s;
  s.max_iterations = n;
  return s;
}

/// A chain of @p n particles of @p m kg below a hard-pinned one, springs of @p k N/m and rest
/// 0.1 m, damped (5/s) so it settles; run 20 s at h = 1/60 s / @p substeps with XPBD, one sweep
/// per step. Returns the largest relative error of a spring's stretch against the weight it
/// carries over k: spring j (from the top, 1-based) holds (n - j + 1) m g.
double chainStretchError(int n, double m, double k, int substeps) {
  Model model;
  model.mass = Eigen::VectorXd::Constant(n + 1, m);
  model.damping = 5.0;
  const double h = 1.0 / 60.0 / substeps;
  Points rest(3, n + 1);
  for (int i = 0; i <= n; ++i) {
    rest.col(i) = Vec3(0.0, 0.0, -0.1 * i);
    if (i > 0) model.springs.add(i - 1, i, 0.1, k, SpringFamily::kStructural);
  }
  PinSet pins;
  pins.add(0, Vec3::Zero(), 0.0, n + 1);
  XpbdSolver solver;
  State state = State::atRest(rest);
  const int steps = 20 * 60 * substeps;
  for (int s = 0; s < steps; ++s) solver.step({model, pins, h, 1}, sweeps(1), state);
  EXPECT_EQ(state.positions.col(0), Vec3::Zero());  // infinite mass: exactly on its target
  double worst = 0.0;
  for (int j = 1; j <= n; ++j) {
    const double stretch = (state.positions.col(j) - state.positions.col(j - 1)).norm() - 0.1;
    const double expected = (n - j + 1) * m * 9.81 / k;
    worst = std::max(worst, std::abs(stretch - expected) / expected);
  }
  return worst;
}

TEST(Xpbd, SelectableByName) {
  EXPECT_STREQ(makeSolver("xpbd")->name(), "xpbd");
}

TEST(Xpbd, OneSpringHangsAtExactlyMgOverKAtAnyStep) {
  // One constraint, one sweep: at rest the prediction x + h^2 g is pulled back by
  // w C / (w + alpha~), C = s + h^2 g, which is h^2 g exactly when s = alpha~ h^2 g / w = m g / k.
  XpbdSolver solver;
  EXPECT_LT(test::staticStretchError(solver, sweeps(1)), 1e-6);
  EXPECT_LT(test::softPinSagError(solver, sweeps(1)), 1e-6);
}

TEST(Xpbd, ChainConvergesToStaticStretchAsSubstepsGrow) {
  // A chain solved by one Gauss-Seidel sweep per step is biased at rest (each correction moves
  // the next spring before it is projected), by about k h^2 / m; small steps remove it as h^2
  // (measured 0.21, 1.3e-2, 8.1e-4, 5.1e-5: 16x per 4x substeps).
  double previous = 1e300;
  for (int substeps : {1, 4, 16, 64}) {
    const double error = chainStretchError(4, 0.1, 100.0, substeps);
    std::printf("substeps %3d: largest relative stretch error %.3e\n", substeps, error);
    EXPECT_LT(error, previous / 12.0) << substeps;
    previous = error;
  }
  EXPECT_LT(previous, 1e-4);
}

TEST(Xpbd, ConservesLinearMomentumWithoutGravityOrPins) {
  XpbdSolver solver;
  EXPECT_LT(test::momentumDrift(solver, sweeps(1), 50), 1e-9);
  EXPECT_LT(test::momentumDrift(solver, sweeps(5), 50), 1e-9);
}

TEST(Xpbd, RefusesWhatItDoesNotSupportNamingTheField) {
  const auto expectRefused = [](const SolverSettings& settings, const std::string& field) {
    SimulationOptions options;
    options.solver = "xpbd";
    options.settings = settings;
    try {
      options.validate();
      ADD_FAILURE() << field << " accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("xpbd"), std::string::npos) << e.what();
    }
  };
  SolverSettings bdf2;
  bdf2.integrator = Integrator::kBdf2;
  expectRefused(bdf2, "solver.integrator = bdf2");
  SolverSettings tolerance;
  tolerance.tolerance = 1e-6;
  expectRefused(tolerance, "solver.tolerance = 1e-06");
  SolverSettings warm;
  warm.warm_start = true;
  expectRefused(warm, "solver.warm_start = true");
  EXPECT_FALSE(XpbdSolver().supports(Integrator::kBdf2));
  // A simulation running another solver with such settings cannot switch to it.
  BuiltObject g = test::makeGrid(3, 3, 100.0, 10.0, 0.0);
  SimulationOptions options;
  options.settings.warm_start = true;
  Simulation sim(g.model, g.rest_positions, PinSet(), Colliders(), options);
  EXPECT_THROW(sim.setSolver("xpbd"), std::invalid_argument);
  EXPECT_STREQ(sim.solver().name(), "local_global");
}

}  // namespace
}  // namespace cloth_sim
