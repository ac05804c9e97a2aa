#include <algorithm>

#include <gtest/gtest.h>

#include "cloth_sim/core/solvers/baselines/local_global_3n_solver.h"
#include "cloth_sim/core/solvers/local_global/local_global_solver.h"
#include "test_util.h"

namespace cloth_sim {
namespace {

TEST(LocalGlobal3n, SameIteratesAsTheScalarFactor) {
  // A hard pin, a soft pin and a moving target: every term of the right-hand side.
  BuiltObject g = test::makeGrid(7, 6, 300.0, 30.0, 3.0);
  const double h = 1.0 / 30.0;
  g.model.damping = 0.2;
  PinSet pins;
  const int hard = pins.add(0, g.rest_positions.col(0), 0.0, 42);
  pins.add(5, g.rest_positions.col(5), 200.0, 42);
  State a = State::atRest(g.rest_positions), b = a;
  LocalGlobalSolver scalar;
  LocalGlobal3nSolver blocked;
  EXPECT_STREQ(blocked.name(), "local_global_3n");
  for (int k = 0; k < 25; ++k) {
    pins.moveTarget(hard, g.rest_positions.col(0) + Vec3(0.01 * k, 0.0, 0.0));
    const SolveResult ra = scalar.step({g.model, pins, h, 1}, test::convergedSettings(7, 0.0), a);
    const SolveResult rb = blocked.step({g.model, pins, h, 1}, test::convergedSettings(7, 0.0), b);
    EXPECT_NEAR(ra.convergence, rb.convergence, 1e-9);
  }
  EXPECT_LT((a.positions - b.positions).norm(), 1e-10 * a.positions.norm());
  EXPECT_LT((a.velocities - b.velocities).norm(), 1e-8 * a.velocities.norm());
  EXPECT_EQ(blocked.factorizationCount(), 1);
}

TEST(LocalGlobal3n, SelectableByName) {
  EXPECT_STREQ(makeSolver("local_global_3n")->name(), "local_global_3n");
  const auto names = solverNames();
  EXPECT_NE(std::find(names.begin(), names.end(), "local_global_3n"), names.end());
}

TEST(LocalGlobal3n, HangingMassSettlesAtStaticStretchMgOverK) {
  LocalGlobal3nSolver solver;
  EXPECT_LT(test::staticStretchError(solver, test::convergedSettings()), 1e-6);
}

}  // namespace
}  // namespace cloth_sim
