// The stability sweep of docs/benchmark.md on a small grid: the implicit solvers are stable in every
// cell (finite, never rolled back, back under 100 % strain by the end of the run).
#include <gtest/gtest.h>

#include "stability.h"

namespace cloth_sim::bench {
namespace {

constexpr int kGrid = 8;
// The benchmark sweep (StabilityOptions' defaults: stiffness, time steps, cases, iterations,
// 3 s with the teleport and the throw at 0.5 s, damping), on a smaller grid.
const StabilityOptions kDefaults;

class ImplicitSolverSweep : public ::testing::TestWithParam<std::string> {};

TEST_P(ImplicitSolverSweep, StableInEveryCell) {
  for (Scenario scenario : kDefaults.scenarios) {
    for (double k : kDefaults.stiffness) {
      for (double h : kDefaults.time_steps) {
        const CellResult r = runCell(scenario, kGrid, k, h, GetParam(), kDefaults.iterations,
                                     kDefaults.duration, kDefaults.damping);
        EXPECT_TRUE(r.stable()) << scenarioName(scenario) << " k " << k << " h " << h
                                << ": rollbacks " << r.rollbacks << ", end strain " << r.end_strain;
        if (scenario == Scenario::kRelease) {
          // Nothing violent happens: no transient either.
          EXPECT_LE(r.peak_strain, 1.0) << "release k " << k << " h " << h;
        }
      }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Implicit, ImplicitSolverSweep,
                         ::testing::Values("local_global", "chebyshev", "anderson", "lbfgs", "newton",
                                           "local_global_3n",
                                           // BDF2 (newton/bdf2 passes too, in 60 s: left out)
                                           "local_global/bdf2", "chebyshev/bdf2"));

TEST(StabilitySweep, DetectsTheExplicitInstability) {
  // The sweep must be able to say "unstable": explicit Euler on stiff cloth at a large step.
  const CellResult r = runCell(Scenario::kRelease, kGrid, 1e4, 1.0 / 60, "explicit_euler", 1, 1.0,
                               kDefaults.damping);
  EXPECT_FALSE(r.stable());
  EXPECT_GT(r.rollbacks, 0);
  // And stable where h omega < 2: soft springs, small step.
  const CellResult soft = runCell(Scenario::kRelease, kGrid, 10.0, 1.0 / 240, "verlet", 1, 1.0,
                                  kDefaults.damping);
  EXPECT_TRUE(soft.stable());
}

}  // namespace
}  // namespace cloth_sim::bench
