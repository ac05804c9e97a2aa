// The table of settings: range rules, their text, and SolverSettings checked against it.
#include <set>
#include <string>

#include <gtest/gtest.h>

#include "cloth_sim/core/settings/settings_table.h"
#include "cloth_sim/core/solvers/registry.h"

namespace cloth_sim {
namespace {

TEST(Range, ContainsHonoursOpenEndsAndRefusesNonFinite) {
  const Range unit_open_max{0, 1, false, true};
  EXPECT_TRUE(unit_open_max.contains(0.0));
  EXPECT_FALSE(unit_open_max.contains(1.0));
  EXPECT_FALSE(Range::above(0).contains(0.0));
  EXPECT_TRUE(Range::atLeast(0).contains(0.0));
  EXPECT_FALSE(Range::atLeast(0).contains(std::numeric_limits<double>::quiet_NaN()));
  EXPECT_FALSE(Range::atLeast(0).contains(Range::kInfinity));
}

TEST(Range, RuleText) {
  EXPECT_EQ((Range{0, 1, false, true}).rule(), "in [0, 1)");
  EXPECT_EQ((Range{0, 1, true, false}).rule(), "in (0, 1]");
  EXPECT_EQ(Range::closed(1, 100000).rule(), "in [1, 100000]");
  EXPECT_EQ(Range::atLeast(0).rule(), ">= 0");
  EXPECT_EQ(Range::above(0.5).rule(), "> 0.5");
}

TEST(SettingsTable, RequirementAndCoreMessage) {
  EXPECT_EQ(settings::kChebyshevRho.requirement(), "in [0, 1) (0 = the upper bound)");
  EXPECT_EQ(settings::kSphereMass.requirement(), "in [0, 1e+09] kg (0 = kinematic)");
  try {
    settings::kIterations.require(0);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "solver.iterations = 0 must be in [1, 100000]");
  }
}

TEST(SettingsTable, NamesAreUniqueAndIntegerRangesHaveIntegerEnds) {
  std::set<std::string> names, params;
  for (const Setting* s : settings::kAllSettings) {
    EXPECT_TRUE(names.insert(s->name).second) << s->name;
    if (*s->param != '\0') {
      EXPECT_TRUE(params.insert(s->param).second) << s->param;
    }
    if (s->integer) {
      EXPECT_EQ(s->range.min, static_cast<long>(s->range.min)) << s->name;
      EXPECT_EQ(s->range.max, static_cast<long>(s->range.max)) << s->name;
    }
  }
}

TEST(SettingsTable, SolverSettingsDefaultsAreAllowedAndValidateUsesTheTable) {
  EXPECT_NO_THROW(SolverSettings{}.validate());
  SolverSettings s;
  s.anderson_window = 51;
  EXPECT_THROW(s.validate(), std::invalid_argument);
  s = SolverSettings{};
  s.chebyshev_gamma = 0.0;
  EXPECT_THROW(s.validate(), std::invalid_argument);
}

TEST(SolverRegistry, MakesEverySolverUnderItsName) {
  for (const SolverEntry& entry : solverRegistry()) {
    EXPECT_STREQ(makeSolver(entry.name)->name(), entry.name);
  }
  EXPECT_EQ(solverNames().size(), solverRegistry().size());
  EXPECT_THROW(makeSolver("rk4"), std::invalid_argument);
}

}  // namespace
}  // namespace cloth_sim
