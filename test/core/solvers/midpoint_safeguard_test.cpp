// MidpointSafeguard: under implicit midpoint a step that gains energy is redone as two implicit
// Euler steps of h/2 by the inner solver, with the same matrix; under any other integrator the
// wrapper is the inner solver, bit for bit.
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "cloth_sim/core/model/spring_kernels.h"
#include "cloth_sim/core/solvers/local_global/local_global_solver.h"
#include "cloth_sim/core/solvers/midpoint_safeguard.h"
#include "test_util.h"

namespace cloth_sim {
namespace {

constexpr Integrator kMidpoint = Integrator::kImplicitMidpoint;
constexpr double kH = 1.0 / 60.0;  ///< s, the step of every test here

SolverSettings settingsFor(Integrator integrator, int iterations = 100, double tolerance = 1e-14) {
  SolverSettings s = test::convergedSettings(iterations, tolerance);
  s.integrator = integrator;
  return s;
}

/// The stability sweep's "release" cell k = 1000 N/m, h = 1/60 s (benchmark.md "Stability"): a
/// 16 x 16, 0.2 kg cloth (shear k/10, bending k/100) hanging from its whole first row, released
/// flat, damping 0.5 / s, 10 local/global iterations per step.
struct Release {
  BuiltObject g;
  PinSet pins;
  Release() {
    GridSpec spec;
    spec.rows = spec.cols = 16;
    spec.material.areal_density = 0.2;
    spec.material.structural = 1000.0;
    spec.material.shear = 100.0;
    spec.material.has_bending = true;
    spec.material.bending = 10.0;
    spec.pose = Eigen::Translation3d(0.0, 0.0, 1.5) * Eigen::Isometry3d::Identity();
    g = buildGrid(spec);
    g.model.damping = 0.5;
    for (int col = 0; col < 16; ++col) pins.add(col, g.rest_positions.col(col), 0.0, 256);
  }
};

TEST(MidpointSafeguard, EnergyGainingStepsAreRedoneAsTwoImplicitEulerHalfSteps) {
  // Plain midpoint steps (the solver alone) on this cell gain energy until the cloth explodes
  // (max strain 5); Simulation (its MidpointSafeguard) redoes the steps that gain energy as two
  // implicit Euler steps of h/2 with the same matrix, and the cloth stays below 50 % strain.
  Release plain;
  State s = State::atRest(plain.g.rest_positions);
  LocalGlobalSolver solver;
  double plain_strain = 0.0;
  for (int n = 0; n < 180 && s.positions.allFinite(); ++n) {
    solver.step({plain.g.model, plain.pins, kH, 1}, settingsFor(kMidpoint, 10, 0.0), s);
    plain_strain = std::max(plain_strain, maxStrain(plain.g.model.springs, s.positions));
  }
  Release guarded;
  SimulationOptions options;
  options.settings = settingsFor(kMidpoint, 10, 0.0);
  options.frame_time = kH;
  Simulation sim(guarded.g.model, guarded.g.rest_positions, guarded.pins, Colliders(), options);
  const double start = sim.totalEnergy();
  int fallbacks = 0, frames_with_fallback = 0;
  double strain = 0.0;
  for (int f = 0; f < 180; ++f) {
    const StepReport r = sim.step();
    ASSERT_EQ(r.status, StepStatus::kOk) << "frame " << f << ": " << r.message;
    fallbacks += r.midpoint_fallbacks;
    frames_with_fallback += r.midpoint_fallbacks > 0 ? 1 : 0;
    strain = std::max(strain, r.max_strain);
  }
  std::printf(
      "release 16 x 16, 3 s: plain midpoint max strain %.3g (finite: %d); with the "
      "safeguard %.3f, %d of 180 steps redone, energy %+.4f J\n",
      plain_strain, static_cast<int>(s.positions.allFinite()), strain, fallbacks,
      sim.totalEnergy() - start);
  EXPECT_TRUE(plain_strain > 1.0 || !s.positions.allFinite());  // measured: 5.0
  EXPECT_LT(strain, 0.5);                                       // measured: 0.17
  EXPECT_GT(fallbacks, 0);
  EXPECT_LT(sim.totalEnergy(), start);     // released at rest, damped: it can only lose energy
  EXPECT_EQ(sim.factorizationCount(), 1);  // the fallback reuses M + (h/2)^2 L
}

TEST(MidpointSafeguard, NeverFiresOnThePeerClothAtItsSubsteps) {
  // The peer cloth (8 x 8, 16 substeps of 1 iteration, undamped): steps lose or keep energy.
  Simulation sim = test::makePeerCloth8(kMidpoint, 1);
  int fallbacks = 0;
  for (int f = 0; f < 120; ++f) fallbacks += sim.step().midpoint_fallbacks;
  std::printf("peer cloth 8 x 8, 2 s at 16 substeps of 1 iteration: %d of 1920 steps redone\n",
              fallbacks);
  EXPECT_EQ(fallbacks, 0);
}

TEST(MidpointSafeguard, IsTheInnerSolverUnderEveryOtherIntegrator) {
  for (Integrator integrator : {Integrator::kImplicitEuler, Integrator::kBdf2}) {
    Release cloth;
    MidpointSafeguard wrapped(std::make_unique<LocalGlobalSolver>());
    LocalGlobalSolver bare;
    State a = State::atRest(cloth.g.rest_positions), b = a;
    for (int n = 0; n < 20; ++n) {
      const SolveResult ra =
          wrapped.step({cloth.g.model, cloth.pins, kH, 1}, settingsFor(integrator, 10, 0.0), a);
      const SolveResult rb =
          bare.step({cloth.g.model, cloth.pins, kH, 1}, settingsFor(integrator, 10, 0.0), b);
      EXPECT_FALSE(ra.midpoint_fallback);
      EXPECT_EQ(ra.iterations, rb.iterations);
    }
    EXPECT_EQ(a.positions, b.positions) << integratorName(integrator);
    EXPECT_EQ(a.velocities, b.velocities) << integratorName(integrator);
    EXPECT_EQ(a.time, b.time);
    EXPECT_EQ(wrapped.factorizationCount(), bare.factorizationCount());
    EXPECT_STREQ(wrapped.name(), "local_global");
  }
}

TEST(MidpointSafeguard, AFallbackIsTwoInnerImplicitEulerStepsOfHalfTheStep) {
  // Run the release cell until a step falls back; that step must equal two implicit Euler
  // steps of h/2 from its start, end h later, and cost no factorization.
  Release cloth;
  MidpointSafeguard wrapped(std::make_unique<LocalGlobalSolver>());
  State s = State::atRest(cloth.g.rest_positions);
  for (int n = 0; n < 180; ++n) {
    const State before = s;
    const SolveResult r =
        wrapped.step({cloth.g.model, cloth.pins, kH, 1}, settingsFor(kMidpoint, 10, 0.0), s);
    if (!r.midpoint_fallback) continue;
    LocalGlobalSolver euler;
    State halves = before;
    const SolverInput half{cloth.g.model, cloth.pins, 0.5 * kH, 1};
    euler.step(half, settingsFor(Integrator::kImplicitEuler, 10, 0.0), halves);
    euler.step(half, settingsFor(Integrator::kImplicitEuler, 10, 0.0), halves);
    EXPECT_EQ(s.positions, halves.positions) << "step " << n;
    EXPECT_EQ(s.velocities, halves.velocities) << "step " << n;
    EXPECT_EQ(s.time, before.time + kH);
    EXPECT_EQ(wrapped.factorizationCount(), 1);  // M + (h/2)^2 L, the midpoint's own matrix
    return;
  }
  ADD_FAILURE() << "no step fell back in 180 (the release cell gains energy under midpoint)";
}

TEST(MidpointSafeguard, AsksTheInnerSolverWhatItSupports) {
  MidpointSafeguard xpbd(makeSolver("xpbd"));
  EXPECT_STREQ(xpbd.name(), "xpbd");
  EXPECT_FALSE(xpbd.supports(kMidpoint));
  EXPECT_THROW(xpbd.requireSettings(settingsFor(kMidpoint, 1)), std::invalid_argument);
  EXPECT_THROW(MidpointSafeguard(nullptr), std::invalid_argument);
}

}  // namespace
}  // namespace cloth_sim
