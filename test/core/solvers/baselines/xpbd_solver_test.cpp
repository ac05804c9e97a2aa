// XPBD, the peers' small-steps baseline: one step against the published update, the colour
// order of the sweep, a stiff cloth at few substeps, static stretch against m g / k,
// momentum, what it refuses. docs/method.md, "XPBD baseline".
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "cloth_sim/core/io/scene_builder.h"
#include "cloth_sim/core/io/scene_overrides.h"
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

/// Two free particles joined by one spring, the step written out from Macklin, Mueller,
/// Chentanez 2016 (Algorithm 1, eq. 18) for a distance constraint C = |x_1 - x_2| - r: from
/// (x, v), @p iterations Gauss-Seidel iterations of one step of h; lambda starts at 0.
struct TwoParticles {
  double m1 = 0.3, m2 = 0.1, k = 200.0, rest = 0.5, damping = 0.4;
  Vec3 g{0.0, 0.0, -9.81};
  void step(Points& x, Points& v, double h, int iterations) const {
    const double w1 = 1.0 / m1, w2 = 1.0 / m2;
    const double alpha_tilde = 1.0 / (k * h * h);  // alpha = 1 / k, scaled by this step's h^2
    Points p(3, 2);
    for (int i = 0; i < 2; ++i) p.col(i) = x.col(i) + h * (std::exp(-damping * h) * v.col(i) + h * g);
    double lambda = 0.0;  // reset every step
    for (int it = 0; it < iterations; ++it) {
      const Vec3 d = p.col(0) - p.col(1);
      const double c = d.norm() - rest;
      const double dlambda = (-c - alpha_tilde * lambda) / (w1 + w2 + alpha_tilde);
      lambda += dlambda;
      p.col(0) += w1 * dlambda * d / d.norm();  // grad_1 C = n, grad_2 C = -n
      p.col(1) -= w2 * dlambda * d / d.norm();
    }
    v = (p - x) / h;
    x = p;
  }
};

TEST(Xpbd, OneStepOnTwoParticlesIsThePublishedUpdate) {
  // Compliance over the step's own h^2, the sign of C and its gradient, lambda carried across
  // the iterations of a step and reset between steps, v = (x_new - x) / h: any of them changed
  // moves the result far more than 1e-12 (the stretched spring is pulled back by ~0.1 m).
  const TwoParticles sys;
  Model model;
  model.mass = Eigen::Vector2d(sys.m1, sys.m2);
  model.damping = sys.damping;
  model.gravity = sys.g;
  model.springs.add(0, 1, sys.rest, sys.k, SpringFamily::kStructural);
  Points x(3, 2), v(3, 2);
  x << 0.0, 0.6, 0.0, 0.1, 0.0, -0.05;
  v << 0.2, -0.3, 0.1, 0.4, -0.2, 0.0;
  State state = State::atRest(x);
  state.velocities = v;
  XpbdSolver solver;
  const double h = 1.0 / 240.0;
  for (int iterations : {1, 3}) {
    for (int step = 0; step < 3; ++step) {  // the later steps start from a moving spring
      solver.step({model, PinSet(), h, 1}, sweeps(iterations), state);
      sys.step(x, v, h, iterations);
      EXPECT_LT((state.positions - x).cwiseAbs().maxCoeff(), 1e-12) << iterations << " " << step;
      EXPECT_LT((state.velocities - v).cwiseAbs().maxCoeff(), 1e-9) << iterations << " " << step;
    }
  }
}

/// hanging (config/scenes/hanging.yaml: 1 m, 0.2 kg/m^2, springs 400/40/4 N/m, two top corners
/// pinned, released flat) at @p n x @p n, run by XPBD at @p substeps of one sweep per 1/60 s
/// frame for @p frames frames; returns the largest particle speed (m/s) seen at a frame's end,
/// and the largest spring strain in @p strain.
double hangingPeakSpeed(int n, int substeps, int frames, double& strain) {
  SceneOverrides resized;
  resized.resolution = n;
  const Simulation sim =
      makeSimulation(applyOverrides(loadSceneFile(test::sourcePath("config/scenes/hanging.yaml")), resized));
  const Model& model = sim.model();
  State state = sim.state();
  XpbdSolver solver;
  const double h = sim.frameTime() / substeps;
  double speed = 0.0;
  strain = 0.0;
  for (int f = 0; f < frames; ++f) {
    for (int s = 0; s < substeps; ++s) solver.step({model, sim.pins(), h, 1}, sweeps(1), state);
    if (!state.allFinite()) return INFINITY;
    speed = std::max(speed, state.velocities.colwise().norm().maxCoeff());
    for (std::size_t k = 0; k < model.springs.size(); ++k) {
      const double length =
          (state.positions.col(model.springs.first[k]) - state.positions.col(model.springs.second[k])).norm();
      strain = std::max(strain, std::abs(length - model.springs.rest_length[k]) / model.springs.rest_length[k]);
    }
  }
  EXPECT_EQ(solver.colourCount(), 13);  // structural, shear (both diagonals), bending
  return speed;
}

TEST(Xpbd, StiffClothStaysFiniteAtFewSubsteps) {
  // k h^2 / m about 140 (64 x 64) and 570 (128 x 128) at 4 substeps: nearly hard constraints.
  // One sweep per substep stretches such a cloth far (XPBD's super-elasticity) but a speed
  // stays that of a fall and a swing (9.8 m/s after 1 s of free fall). Measured 9.8 and
  // 4.8 m/s (max strain 20 and 40); the sweep in model order instead of colour by colour
  // reached 2.4e4 and 100 m/s (strain 5,800 and 67) and grew without bound after.
  double strain = 0.0;
  const double speed64 = hangingPeakSpeed(64, 4, 60, strain);
  std::printf("64 x 64, 4 substeps, 1 s: peak speed %.3g m/s, max strain %.3g\n", speed64, strain);
  EXPECT_LT(speed64, 20.0);
  EXPECT_LT(strain, 50.0);
  const double speed128 = hangingPeakSpeed(128, 4, 30, strain);
  std::printf("128 x 128, 4 substeps, 0.5 s: peak speed %.3g m/s, max strain %.3g\n", speed128, strain);
  EXPECT_LT(speed128, 20.0);
  EXPECT_LT(strain, 60.0);
}

TEST(Xpbd, SweepsTheSpringsColourByColour) {
  // A chain 0-1-2-3-4: colours {01, 23} and {12, 34}. One sweep of hard constraints (k huge)
  // on the chain stretched to twice its rest lengths, 0 hard-pinned: in colour order 01 and 23
  // first, then 12 and 34. Worked by hand (w equal, alpha~ ~ 0): positions along the chain
  // 0, 2, 4, 6, 8 (rest 1): 01 -> x1 = 1; 23 -> x2 = 4.5, x3 = 5.5; 12 -> |4.5 - 1| = 3.5,
  // x1 = 2.25, x2 = 3.25; 34 -> |8 - 5.5| = 2.5, x3 = 6.25, x4 = 7.25. In model order one
  // sweep would give 0, 2, 4, 6, 7: the whole chain's correction carried to its free end.
  Model model;
  model.mass = Eigen::VectorXd::Constant(5, 1.0);
  model.gravity.setZero();
  Points x(3, 5);
  for (int i = 0; i < 5; ++i) {
    x.col(i) = Vec3(2.0 * i, 0.0, 0.0);
    if (i > 0) model.springs.add(i - 1, i, 1.0, 1e12, SpringFamily::kStructural);
  }
  PinSet pins;
  pins.add(0, Vec3::Zero(), 0.0, 5);
  State state = State::atRest(x);
  XpbdSolver solver;
  solver.step({model, pins, 0.01, 1}, sweeps(1), state);
  EXPECT_EQ(solver.colourCount(), 2);
  const double expected[] = {0.0, 2.25, 3.25, 6.25, 7.25};
  for (int i = 0; i < 5; ++i) EXPECT_NEAR(state.positions(0, i), expected[i], 1e-6) << i;
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
  // the next spring before it is projected): in the colour order, by 2 k h^2 / m for the worst
  // spring (measured 0.556, 3.47e-2, 2.17e-3, 1.36e-4; k h^2 / m = 0.278 at 1 substep), 16x
  // less per 4x substeps. (The sweep in model order, top down, was biased 2.7x less: 0.21 at
  // 1 substep, 5.1e-5 at 64, but it diverged on stiff cloths; see StiffClothStaysFinite.)
  double previous = 1e300;
  for (int substeps : {1, 4, 16, 64}) {
    const double error = chainStretchError(4, 0.1, 100.0, substeps);
    std::printf("substeps %3d: largest relative stretch error %.3e\n", substeps, error);
    EXPECT_LT(error, previous / 12.0) << substeps;
    previous = error;
  }
  EXPECT_LT(previous, 2e-4);
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
