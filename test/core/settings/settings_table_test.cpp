// The table of settings: range rules, their text, the one refusal message, and SolverSettings
// checked against it.
#include <cmath>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "cloth_sim/core/settings/settings_table.h"
#include "cloth_sim/core/solvers/local_global/lbfgs_solver.h"
#include "cloth_sim/core/solvers/local_global/local_global_solver.h"
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
    EXPECT_STREQ(e.what(), "solver.iterations 0 must be in [1, 100000]");
  }
}

TEST(SettingsTable, TheRefusalStatesValueUnitRuleAndNote) {
  EXPECT_EQ(settings::kSphereRadius.refusal(0.1, "radius"), "");
  EXPECT_EQ(settings::kSphereRadius.refusal(0.0, "radius"), "radius 0 must be in (0, 1e+06] m");
  EXPECT_EQ(settings::kSphereMass.refusal(-1, "mass"),
            "mass -1 must be in [0, 1e+09] kg (0 = kinematic)");
  // An unbounded range says what a bounded one implies; an integer setting says "an integer"
  // for a value that is not one.
  EXPECT_EQ(settings::kGraspFrameTimeout.refusal(0.0, "parameter '~grasp_frame_timeout':"),
            "parameter '~grasp_frame_timeout': 0 must be finite and > 0 s");
  EXPECT_EQ(settings::kMaxRollbacks.refusal(0, "max_rollbacks"), "max_rollbacks 0 must be >= 1");
  EXPECT_EQ(settings::kGridResolution.refusal(2.5, "value"),
            "value 2.5 must be an integer in [2, 2000]");
  EXPECT_EQ(settings::kGridResolution.requirement(), "an integer in [2, 2000]");
  // A value just outside an end is shown with the digits that tell it from the end.
  EXPECT_EQ(settings::kTimeStep.refusal(std::nextafter(1e-6, 0.0), "time_step"),
            "time_step 9.999999999999997e-07 must be in [1e-06, 1] s");
}

/// Values just outside each end of @p s's range (an open end itself), and NaN.
std::vector<double> justOutside(const Setting& s) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> values = {nan};
  const double step = s.integer ? 1.0 : 0.0;
  if (std::isfinite(s.range.min)) {
    values.push_back(s.range.min_open ? s.range.min
                     : s.integer      ? s.range.min - step
                                      : std::nextafter(s.range.min, -Range::kInfinity));
  }
  if (std::isfinite(s.range.max)) {
    values.push_back(s.range.max_open ? s.range.max
                     : s.integer      ? s.range.max + step
                                      : std::nextafter(s.range.max, Range::kInfinity));
  }
  return values;
}

/// Every setting: the table's and each solver's own (its registry entry's block).
std::vector<const Setting*> everySetting() {
  std::vector<const Setting*> all(std::begin(settings::kAllSettings),
                                  std::end(settings::kAllSettings));
  for (const SolverEntry& entry : solverRegistry()) {
    for (const SolverParam* param : entry.params) all.push_back(param);
  }
  return all;
}

TEST(SettingsTable, EveryRefusalNamesTheFieldAndStatesTheRange) {
  for (const Setting* s : everySetting()) {
    for (const double value : justOutside(*s)) {
      SCOPED_TRACE(std::string(s->name) + " = " + formatNumber(value, 17));
      EXPECT_FALSE(s->allows(value));
      std::string message;
      try {
        s->require(value);
      } catch (const std::invalid_argument& e) {
        message = e.what();
      }
      EXPECT_EQ(message, s->refusal(value, s->name));
      EXPECT_EQ(message.rfind(std::string(s->name) + " ", 0), 0u) << message;  // names the field
      // States the range: both ends, each bracket as it is, and the unit.
      const std::string range = s->range.rule();
      EXPECT_NE(message.find(" must be "), std::string::npos) << message;
      EXPECT_NE(message.find(range), std::string::npos) << message << " lacks " << range;
      if (*s->unit != '\0') {
        EXPECT_NE(message.find(range + " " + s->unit), std::string::npos) << message;
      }
      if (*s->note != '\0') {
        EXPECT_NE(message.find(s->note), std::string::npos) << message;
      }
      // The value shown is the one refused, not an end it rounds to.
      const std::size_t from = std::string(s->name).size() + 1;
      const std::string shown = message.substr(from, message.find(' ', from) - from);
      const double read = std::strtod(shown.c_str(), nullptr);
      EXPECT_FALSE(s->allows(read)) << shown << " reads as allowed";
    }
  }
}

TEST(SettingsTable, NamesAreUniqueAndIntegerRangesHaveIntegerEnds) {
  std::set<std::string> names, params;
  for (const Setting* s : everySetting()) {
    EXPECT_TRUE(names.insert(s->name).second) << s->name;
    if (*s->param != '\0') {
      EXPECT_TRUE(params.insert(s->param).second) << s->param;
    }
    if (s->integer) {  // an open-ended integer range (">= 1") has an infinite end
      for (const double end : {s->range.min, s->range.max}) {
        if (std::isfinite(end)) {
          EXPECT_EQ(end, static_cast<long>(end)) << s->name;
        }
      }
    }
  }
}

TEST(SettingsTable, SolverSettingsDefaultsAreAllowedAndValidateUsesTheTable) {
  EXPECT_NO_THROW(SolverSettings{}.validate());
  SolverSettings s;
  s.params.set(settings::kAndersonWindow, 51);
  EXPECT_THROW(s.validate(), std::invalid_argument);
  s = SolverSettings{};
  s.params.set(settings::kChebyshevGamma, 0.0);
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
