// FrameBudget: the substeps per frame that fit a wall-clock budget, driven here by a synthetic
// frame-time model (a cost per substep, a fixed per-frame cost, seeded noise).
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "cloth_sim/core/simulation/frame_budget.h"

namespace cloth_sim {
namespace {

constexpr unsigned kSeed = 20261123;

/// A machine whose frame costs overhead + substeps x per_substep seconds, times 1 +- noise.
struct FakeMachine {
  double per_substep;
  double overhead;
  double noise;
  std::mt19937 rng{kSeed};
  double frame(int substeps) {
    std::uniform_real_distribution<double> u(-noise, noise);
    return (overhead + substeps * per_substep) * (1.0 + u(rng));
  }
};

/// Runs @p frames frames from @p substeps; returns the substeps of every frame.
std::vector<int> drive(FrameBudget& budget, FakeMachine& machine, int substeps, int frames) {
  std::vector<int> history;
  for (int f = 0; f < frames; ++f) {
    history.push_back(substeps);
    substeps = budget.next(substeps, machine.frame(substeps));
  }
  return history;
}

int changes(const std::vector<int>& history, std::size_t from) {
  int n = 0;
  for (std::size_t i = from + 1; i < history.size(); ++i) n += history[i] != history[i - 1];
  return n;
}

TEST(FrameBudget, RefusesBudgetsAndRangesThatCannotBeMet) {
  for (double bad : {0.0, -0.001, std::nan(""), std::numeric_limits<double>::infinity()}) {
    EXPECT_THROW(FrameBudget(bad, 1, 10), std::invalid_argument) << bad;
  }
  EXPECT_THROW(FrameBudget(0.008, 0, 10), std::invalid_argument);
  EXPECT_THROW(FrameBudget(0.008, 5, 4), std::invalid_argument);
  EXPECT_NO_THROW(FrameBudget(0.008, 3, 3));
}

TEST(FrameBudget, SettlesOnTheMostSubstepsThatFitAndStaysThere) {
  SCOPED_TRACE("seed " + std::to_string(kSeed));
  const double budget_s = 0.008;
  FrameBudget budget(budget_s, 1, 1000);
  FakeMachine machine{0.0005, 0.0003, 0.1};
  const std::vector<int> history = drive(budget, machine, 1, 1200);
  // What fits the aimed share of the budget on average: (0.85 x 8 - 0.3) / 0.5 = 13 substeps.
  const int settled = history.back();
  EXPECT_GE(settled, 11);
  EXPECT_LE(settled, 14);
  EXPECT_LE(settled * machine.per_substep + machine.overhead, budget_s);
  EXPECT_LE(changes(history, 600), 2) << "the choice keeps flipping";
  // Growing by at most a quarter at a time: from 1 to 13 takes several patient steps.
  EXPECT_LT(history[FrameBudget::kPatience], 3);
}

TEST(FrameBudget, ComesDownWithinAFewFramesWhenTheMachineSlowsDown) {
  FrameBudget budget(0.008, 1, 1000);
  FakeMachine machine{0.0005, 0.0003, 0.05};
  int substeps = drive(budget, machine, 8, 900).back();
  machine.per_substep *= 2.5;  // another process takes the core
  const std::vector<int> after = drive(budget, machine, substeps, 40);
  int first_under = -1;
  for (std::size_t f = 0; f < after.size(); ++f) {
    if (after[f] * machine.per_substep + machine.overhead <= 0.008) {
      first_under = static_cast<int>(f);
      break;
    }
  }
  ASSERT_GE(first_under, 0) << "never back under budget";
  EXPECT_LE(first_under, 15);
  EXPECT_LT(after.back(), substeps);
}

TEST(FrameBudget, KeepsWithinItsSubstepRange) {
  FrameBudget cheap(0.008, 1, 4);
  FakeMachine fast{1e-6, 0.0, 0.0};
  EXPECT_EQ(drive(cheap, fast, 1, 600).back(), 4);
  FrameBudget dear(0.008, 2, 50);
  FakeMachine slow{0.01, 0.0, 0.0};  // one substep alone is over budget
  const std::vector<int> history = drive(dear, slow, 10, 100);
  EXPECT_EQ(history.back(), 2);
  for (int s : history) EXPECT_GE(s, 2);
}

TEST(FrameBudget, IgnoresFramesWithoutAUsableTime) {
  FrameBudget budget(0.008, 1, 100);
  for (double bad : {0.0, -1.0, std::nan(""), std::numeric_limits<double>::infinity()}) {
    EXPECT_EQ(budget.next(7, bad), 7);
  }
  EXPECT_EQ(budget.substepCost(), 0.0);
}

TEST(FrameBudget, SameFrameTimesGiveTheSameChoices) {
  FrameBudget a(0.008, 1, 1000), b(0.008, 1, 1000);
  FakeMachine ma{0.0004, 0.0002, 0.2}, mb{0.0004, 0.0002, 0.2};
  EXPECT_EQ(drive(a, ma, 1, 500), drive(b, mb, 1, 500));
}

}  // namespace
}  // namespace cloth_sim
