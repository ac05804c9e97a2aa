#include <stdexcept>

#include <gtest/gtest.h>

#include "cloth_sim/core/solvers/revision_cache.h"

namespace cloth_sim {
namespace {

TEST(RevisionCache, RebuildsOnlyWhenTheRevisionOrTheLinearSolverChanges) {
  RevisionCache cache;
  int builds = 0;
  const auto build = [&] { ++builds; };
  EXPECT_TRUE(cache.ensure(1, LinearSolver::kFused, build));  // first use
  EXPECT_FALSE(cache.ensure(1, LinearSolver::kFused, build));
  EXPECT_TRUE(cache.ensure(2, LinearSolver::kFused, build));  // new revision
  EXPECT_TRUE(cache.ensure(2, LinearSolver::kEigen, build));  // new linear solver
  EXPECT_FALSE(cache.ensure(2, build));                       // revision only: still built
  EXPECT_TRUE(cache.ensure(3, build));
  EXPECT_EQ(builds, 4);
}

TEST(RevisionCache, RebuildsWhenTheImplicitStepChanges) {
  // BDF2: the first step's matrix has h_i = h, the next ones 2h/3, same revision.
  RevisionCache cache;
  int builds = 0;
  const auto build = [&] { ++builds; };
  const double h = 1.0 / 60.0;
  EXPECT_TRUE(cache.ensure(1, LinearSolver::kFused, h, build));
  EXPECT_TRUE(cache.ensure(1, LinearSolver::kFused, 2.0 * h / 3.0, build));
  EXPECT_FALSE(cache.ensure(1, LinearSolver::kFused, 2.0 * h / 3.0, build));
  EXPECT_EQ(builds, 2);
}

TEST(RevisionCache, AFailedRebuildIsRetried) {
  RevisionCache cache;
  EXPECT_THROW(cache.ensure(1, [] { throw std::runtime_error("factorization failed"); }),
               std::runtime_error);
  int builds = 0;
  EXPECT_TRUE(cache.ensure(1, [&] { ++builds; }));
  EXPECT_EQ(builds, 1);
}

}  // namespace
}  // namespace cloth_sim
