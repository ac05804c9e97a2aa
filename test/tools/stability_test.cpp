// The stability sweep of the README on a small grid: the implicit solvers are stable in every
// cell (finite, never rolled back, back under 100 % strain by the end of the run).
#include <gtest/gtest.h>

#include "stability.h"

namespace cloth_sim::bench {
namespace {

constexpr int kGrid = 8;
// The README sweep's duration (3 s; the teleport and the throw happen at 0.5 s) and damping.
const StabilityOptions kDefaults;
const double kDuration = kDefaults.duration;
const double kDamping = kDefaults.damping;
const std::vector<double> kStiffness = {1e1, 1e2, 1e3, 1e4, 1e5, 1e6};
const std::vector<double> kSteps = {1.0 / 240, 1.0 / 120, 1.0 / 60, 1.0 / 30, 1.0 / 15};

class ImplicitSolverSweep : public ::testing::TestWithParam<std::string> {};

TEST_P(ImplicitSolverSweep, StableInEveryCell) {
  for (Scenario scenario : {Scenario::kRelease, Scenario::kTeleport, Scenario::kSphere}) {
    for (double k : kStiffness) {
      for (double h : kSteps) {
        const CellResult r = runCell(scenario, kGrid, k, h, GetParam(), 10, kDuration, kDamping);
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
                                           "local_global_3n"));

TEST(StabilitySweep, DetectsTheExplicitInstability) {
  // The sweep must be able to say "unstable": explicit Euler on stiff cloth at a large step.
  const CellResult r = runCell(Scenario::kRelease, kGrid, 1e4, 1.0 / 60, "explicit_euler", 1, 1.0, kDamping);
  EXPECT_FALSE(r.stable());
  EXPECT_GT(r.rollbacks, 0);
  // And stable where h omega < 2: soft springs, small step.
  const CellResult soft = runCell(Scenario::kRelease, kGrid, 10.0, 1.0 / 240, "verlet", 1, 1.0, kDamping);
  EXPECT_TRUE(soft.stable());
}

}  // namespace
}  // namespace cloth_sim::bench
