// Coulomb friction on the ground at the scene format's default (error control), for every
// solver that iterates to a tolerance: inside the friction cone a sheet does not creep;
// outside it slides with a = g_t - mu g_n (docs/method.md, "Friction").
#include <algorithm>
#include <cstdio>

#include <gtest/gtest.h>

#include "cloth_sim/core/io/scene.h"
#include "cloth_sim/core/solvers/registry.h"

namespace cloth_sim {
namespace {

constexpr double kMu = 0.5;
constexpr double kNormalGravity = 9.81;  // m/s^2

/// A 0.5 m sheet (6 x 6) lying on the ground under gravity tilted by @p g_tangent along x, with
/// the scene format's defaults for everything about the solver but its name.
SceneConfig sheetOnGround(const std::string& solver, double g_tangent, double height = 0.0) {
  SceneConfig s = parseScene(
      "time_step: 1/60\n"
      "gravity: [" + std::to_string(g_tangent) + ", 0, -9.81]\n"
      "solver: {name: " + solver + "}\n"
      "cloth: {grid: {rows: 6, cols: 6, size: [0.5, 0.5], position: [0, 0, " +
      std::to_string(height) + "]}}\n"
      "material: {areal_density: 0.2, springs: {structural: 1000, shear: 1000}}\n"
      "colliders: {ground: {height: 0, friction: 0.5}}\n",
      "sheet_on_ground");
  return s;
}

double meanX(const Simulation& sim) { return sim.state().positions.row(0).mean(); }

/// The solvers that take the error-controlled default (they iterate to a tolerance) and solve
/// contacts in the step or after it.
std::vector<std::string> iterativeSolvers() {
  return solverNamesWith(&SolverCapabilities::tolerance);
}

TEST(Friction, ASheetInsideTheConeDoesNotCreepForAnySolverAtTheDefault) {
  // g_t = 3 < mu g_n = 4.9: static friction holds the sheet.
  for (const std::string& solver : iterativeSolvers()) {
    Simulation sim = makeSimulation(sheetOnGround(solver, 3.0));
    ASSERT_GT(sim.solverSettings().error_tolerance, 0.0) << solver << ": the default";
    const double start = meanX(sim);
    for (int f = 0; f < 600; ++f) ASSERT_EQ(sim.step().status, StepStatus::kOk) << solver;
    const double creep = std::abs(meanX(sim) - start);
    std::printf("[measured] %-14s creep in 10 s: %.3g m\n", solver.c_str(), creep);
    EXPECT_LT(creep, 1e-6) << solver;
  }
}

// Falling 5 cm under gravity tilted inside the cone, the sheet lands moving sideways at
// 0.3 m/s and friction stops it at once. A stop is a sudden change of velocity, which BDF2's
// history reads as a deceleration: unless the velocity and its history restart whole when the
// contact sticks, BDF2 sends the particles back the way they came.
TEST(Friction, ASheetLandingInsideTheConeStopsWithoutSlidingBack) {
  for (const std::string& solver : iterativeSolvers()) {
    Simulation sim = makeSimulation(sheetOnGround(solver, 3.0, 0.05));
    double furthest = meanX(sim), back = 0.0;
    for (int f = 0; f < 120; ++f) {
      ASSERT_EQ(sim.step().status, StepStatus::kOk) << solver;
      furthest = std::max(furthest, meanX(sim));
      back = std::max(back, furthest - meanX(sim));
    }
    const double speed = sim.state().velocities.colwise().norm().maxCoeff();
    std::printf("[measured] %-14s slid back %.3g m after landing, speed at 2 s %.3g m/s\n",
                solver.c_str(), back, speed);
    EXPECT_LT(back, 1e-6) << solver;
    EXPECT_LT(speed, 1e-6) << solver;
  }
}

TEST(Friction, ASheetOutsideTheConeSlidesAtGTangentMinusMuGNormal) {
  // g_t = 6 > mu g_n: the sheet slides with a = 6 - 0.5 x 9.81 = 1.095 m/s^2 from rest.
  const double g_t = 6.0, a = g_t - kMu * kNormalGravity, t = 1.0;
  for (const std::string& solver : iterativeSolvers()) {
    Simulation sim = makeSimulation(sheetOnGround(solver, g_t));
    const double start = meanX(sim);
    while (sim.state().time < t - 1e-9) ASSERT_EQ(sim.step().status, StepStatus::kOk) << solver;
    const double slid = meanX(sim) - start, exact = 0.5 * a * t * t;
    std::printf("[measured] %-14s slid %.7f m in 1 s, exact %.7f m (relative %.2g)\n",
                solver.c_str(), slid, exact, std::abs(slid - exact) / exact);
    EXPECT_NEAR(slid, exact, 1e-3 * exact) << solver;
  }
}

}  // namespace
}  // namespace cloth_sim
