// StepMonitor (timing, rollbacks, the reset policy), assess() and LogThrottle, no master.
#include <string>

#include <gtest/gtest.h>

#include "cloth_sim/node/log_throttle.h"
#include "cloth_sim/node/step_monitor.h"

namespace cloth_sim::node {
namespace {

constexpr double kBudget = 0.01;  // s

TEST(StepMonitor, WindowCountsStepsOverrunsAndTimes) {
  StepMonitor m(kBudget, 3);
  EXPECT_FALSE(m.record(false, 0.004));
  EXPECT_FALSE(m.record(false, 0.012));  // over budget
  EXPECT_FALSE(m.record(false, 0.008));
  const StepWindow w = m.takeWindow();
  EXPECT_EQ(w.steps, 3);
  EXPECT_EQ(w.overruns, 1);
  EXPECT_EQ(w.rollbacks, 0);
  EXPECT_NEAR(w.mean_time, 0.008, 1e-12);
  EXPECT_EQ(w.max_time, 0.012);
  EXPECT_EQ(w.budget, kBudget);
  // A new window starts empty; totals carry on.
  const StepWindow next = m.takeWindow();
  EXPECT_EQ(next.steps, 0);
  EXPECT_EQ(next.mean_time, 0.0);
  EXPECT_EQ(m.totalOverruns(), 1u);
}

TEST(StepMonitor, ResetsAfterMaxRollbacksInARowOnly) {
  StepMonitor m(kBudget, 3);
  EXPECT_FALSE(m.record(true, 0.001));
  EXPECT_FALSE(m.record(true, 0.001));
  EXPECT_EQ(m.consecutiveFailures(), 2u);
  EXPECT_FALSE(m.record(false, 0.001));  // a good step breaks the run
  EXPECT_EQ(m.consecutiveFailures(), 0u);
  EXPECT_FALSE(m.record(true, 0.001));
  EXPECT_FALSE(m.record(true, 0.001));
  EXPECT_TRUE(m.record(true, 0.001));  // third in a row: reset now
  EXPECT_EQ(m.consecutiveFailures(), 0u);
  EXPECT_EQ(m.divergenceResets(), 1u);
  EXPECT_EQ(m.totalRollbacks(), 5u);
  const StepWindow w = m.takeWindow();
  EXPECT_EQ(w.rollbacks, 5);
  EXPECT_EQ(w.resets, 1);
}

TEST(StepMonitor, AHoldReplacesTheResetAndCutFramesAreCounted) {
  StepMonitor m(kBudget, 2);
  EXPECT_FALSE(m.record(true, 0.001));
  EXPECT_TRUE(m.record(true, 0.001));
  EXPECT_EQ(m.divergenceResets(), 1u);
  EXPECT_FALSE(m.record(true, 0.001));
  EXPECT_TRUE(m.record(true, 0.001));  // the same cause again: the node holds it instead
  m.holdInsteadOfReset();
  EXPECT_EQ(m.divergenceResets(), 1u);
  EXPECT_FALSE(m.record(false, 0.3, /*cut=*/true));
  const StepWindow w = m.takeWindow();
  EXPECT_EQ(w.resets, 1);
  EXPECT_EQ(w.cut, 1);
}

TEST(StepMonitor, ClearFailuresForgetsTheRun) {
  StepMonitor m(kBudget, 2);
  EXPECT_FALSE(m.record(true, 0.001));
  m.clearFailures();
  EXPECT_FALSE(m.record(true, 0.001));
  EXPECT_TRUE(m.record(true, 0.001));
}

TEST(StepMonitor, RefusesABadBudgetOrLimit) {
  EXPECT_THROW(StepMonitor(0.0, 3), std::invalid_argument);
  EXPECT_THROW(StepMonitor(kBudget, 0), std::invalid_argument);
}

StepWindow window(int steps, int overruns, int rollbacks, int resets) {
  StepWindow w;
  w.steps = steps;
  w.overruns = overruns;
  w.rollbacks = rollbacks;
  w.resets = resets;
  w.budget = kBudget;
  w.mean_time = 0.002;
  return w;
}

TEST(Assess, LevelsAndMessages) {
  HealthReport r = assess(window(60, 0, 0, 0));
  EXPECT_EQ(r.level, Health::kOk);
  EXPECT_NE(r.message.find("60 steps, mean 2.00 ms of the 10.00 ms budget"), std::string::npos)
      << r.message;

  r = assess(window(60, 6, 0, 0));  // exactly 10 %: tolerated
  EXPECT_EQ(r.level, Health::kOk);
  r = assess(window(60, 7, 0, 0));
  EXPECT_EQ(r.level, Health::kWarn);
  EXPECT_NE(r.message.find("slower than real time: 7 of 60"), std::string::npos) << r.message;

  r = assess(window(60, 0, 2, 0));
  EXPECT_EQ(r.level, Health::kWarn);
  EXPECT_NE(r.message.find("2 of 60 steps diverged"), std::string::npos) << r.message;

  r = assess(window(60, 0, 30, 1));
  EXPECT_EQ(r.level, Health::kError);
  EXPECT_NE(r.message.find("reset 1 time(s)"), std::string::npos) << r.message;

  r = assess(window(0, 0, 0, 0));
  EXPECT_EQ(r.level, Health::kWarn);
  EXPECT_NE(r.message.find("no step"), std::string::npos);
}

TEST(LogThrottle, OncePerPeriodPerText) {
  LogThrottle t(5.0);
  EXPECT_TRUE(t.allow("pin 3: no pin with id 3", 100.0));
  EXPECT_FALSE(t.allow("pin 3: no pin with id 3", 101.0));
  EXPECT_TRUE(t.allow("radius -1 m must be > 0", 101.0));  // another kind: not hidden
  EXPECT_FALSE(t.allow("pin 3: no pin with id 3", 104.9));
  EXPECT_TRUE(t.allow("pin 3: no pin with id 3", 105.0));
}

TEST(LogThrottle, PruningKeepsRecentTexts) {
  LogThrottle t(5.0);
  EXPECT_TRUE(t.allow("recent", 99.0));
  for (int i = 0; i < 400; ++i) EXPECT_TRUE(t.allow("old " + std::to_string(i), 90.0));
  EXPECT_TRUE(t.allow("trigger a prune", 100.0));
  EXPECT_FALSE(t.allow("recent", 100.0));  // still throttled after the prune
}

}  // namespace
}  // namespace cloth_sim::node
