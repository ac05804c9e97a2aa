// ReconfigureBridge: what a dynamic_reconfigure request changes in the simulation and the node,
// what it refuses and why, and the config that reflects what is in use. No master.
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "cloth_sim/core/io/scene.h"
#include "cloth_sim/node/reconfigure_bridge.h"

namespace cloth_sim::node {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// A small vertical sheet with structural and shear springs and no bending ones (the scene of
/// the reconfigure rostest), with the node's tunables beside it.
struct Fixture {
  Simulation sim = makeSimulation(
      loadSceneFile(std::string(CLOTH_SIM_SOURCE_DIR) + "/test/node/config/sag.yaml"));
  std::optional<FrameBudget> budget;
  ColorMode color_mode = ColorMode::kStrain;
  ReconfigureBridge bridge{sim, budget, color_mode};
};

std::vector<std::string> fieldsOf(const std::vector<FieldOutcome>& outcomes) {
  std::vector<std::string> fields;
  for (const FieldOutcome& o : outcomes) fields.push_back(o.field);
  return fields;
}

TEST(ReconfigureBridge, TheCurrentConfigIsWhatIsInUse) {
  Fixture f;
  const ClothSimConfig c = f.bridge.current();
  EXPECT_EQ(c.structural_stiffness, 50.0);
  EXPECT_EQ(c.shear_stiffness, 5.0);
  EXPECT_EQ(c.bending_stiffness, 0.0);
  EXPECT_EQ(c.damping, 3.0);
  EXPECT_EQ(c.solver, "local_global");
  EXPECT_EQ(c.iterations, 10);
  EXPECT_EQ(c.substeps, f.sim.solverSettings().substeps);
  EXPECT_EQ(c.budget_ms, 0.0);
  EXPECT_FALSE(c.self_collision);
  EXPECT_EQ(c.color_mode, "strain");
}

TEST(ReconfigureBridge, AnUnchangedRequestChangesNothing) {
  Fixture f;
  ClothSimConfig c = f.bridge.current();
  EXPECT_TRUE(f.bridge.apply(c).empty());
  EXPECT_EQ(f.sim.model().damping, 3.0);
}

TEST(ReconfigureBridge, EveryFieldChangesWhatItNames) {
  Fixture f;
  const double frame = f.sim.frameTime();
  ClothSimConfig c = f.bridge.current();
  c.structural_stiffness = 80.0;
  c.shear_stiffness = 8.0;
  c.damping = 1.0;
  c.solver = "chebyshev";
  c.color_mode = "shaded";
  c.iterations = 25;
  c.substeps = 4;
  c.budget_ms = 5.0;
  c.self_collision = true;
  const std::vector<FieldOutcome> outcomes = f.bridge.apply(c);
  EXPECT_EQ(fieldsOf(outcomes),
            (std::vector<std::string>{"structural_stiffness", "shear_stiffness", "damping",
                                      "solver", "color_mode", "iterations", "substeps", "budget_ms",
                                      "self_collision"}));
  for (const FieldOutcome& o : outcomes) EXPECT_TRUE(o.applied) << o.field << ": " << o.why;

  EXPECT_EQ(f.sim.model().familyStiffness(SpringFamily::kStructural), 80.0);
  EXPECT_EQ(f.sim.model().familyStiffness(SpringFamily::kShear), 8.0);
  EXPECT_EQ(f.sim.model().damping, 1.0);
  EXPECT_STREQ(f.sim.solver().name(), "chebyshev");
  EXPECT_EQ(f.sim.solverSettings().max_iterations, 25);
  EXPECT_EQ(f.sim.solverSettings().substeps, 4);
  EXPECT_EQ(f.sim.frameTime(), frame);  // substeps split the frame, which stays
  ASSERT_TRUE(f.budget.has_value());
  EXPECT_DOUBLE_EQ(f.budget->budget(), 5e-3);
  EXPECT_NE(f.sim.selfContact(), nullptr);
  EXPECT_EQ(f.color_mode, ColorMode::kShaded);

  const ClothSimConfig now = f.bridge.current();  // reported back as applied
  EXPECT_EQ(now.structural_stiffness, 80.0);
  EXPECT_EQ(now.solver, "chebyshev");
  EXPECT_DOUBLE_EQ(now.budget_ms, 5.0);
  EXPECT_TRUE(now.self_collision);
  EXPECT_EQ(now.color_mode, "shaded");

  c = f.bridge.current();  // and off again
  c.budget_ms = 0.0;
  c.self_collision = false;
  for (const FieldOutcome& o : f.bridge.apply(c))
    EXPECT_TRUE(o.applied) << o.field << ": " << o.why;
  EXPECT_FALSE(f.budget.has_value());
  EXPECT_EQ(f.sim.selfContact(), nullptr);
}

TEST(ReconfigureBridge, ARefusedFieldIsPutBackWithTheCoresReasonAndTheOthersStillApply) {
  struct Case {
    const char* field;
    void (*spoil)(ClothSimConfig&);
    const char* why;
  };
  const Case cases[] = {
      {"bending_stiffness", [](ClothSimConfig& c) { c.bending_stiffness = 7.0; },
       "this object has no bending springs"},
      {"structural_stiffness", [](ClothSimConfig& c) { c.structural_stiffness = -1.0; },
       "structural stiffness -1 must be in [0, 1e+09] N/m"},
      {"shear_stiffness", [](ClothSimConfig& c) { c.shear_stiffness = kNaN; },
       "shear stiffness nan"},
      {"damping", [](ClothSimConfig& c) { c.damping = -2.0; },
       "damping -2 must be in [0, 1e+06] 1/s"},
      {"solver", [](ClothSimConfig& c) { c.solver = "rk4"; }, "unknown solver 'rk4'"},
      {"color_mode", [](ClothSimConfig& c) { c.color_mode = "red"; },
       "color mode 'red' must be 'strain' or 'shaded'"},
      {"iterations", [](ClothSimConfig& c) { c.iterations = 0; }, "solver.iterations 0 must be in [1, 100000]"},
      {"substeps", [](ClothSimConfig& c) { c.substeps = -3; }, "solver.substeps -3 must be in [0, 1000]"},
      {"error_tolerance", [](ClothSimConfig& c) { c.error_tolerance = -1.0; },
       "solver.error_tolerance -1 must be in [0, 1] m"},
      {"budget_ms", [](ClothSimConfig& c) { c.budget_ms = 2000.0; }, "budget_ms 2000 must be in [0, 1000] ms"},
      {"budget_ms", [](ClothSimConfig& c) { c.budget_ms = kNaN; }, "budget_ms nan must be in [0, 1000] ms"},
  };
  for (const Case& k : cases) {
    SCOPED_TRACE(k.field);
    Fixture f;
    const ClothSimConfig before = f.bridge.current();
    ClothSimConfig c = before;
    k.spoil(c);
    c.damping = k.field == std::string("damping") ? c.damping : 1.5;  // a good change beside it
    const std::vector<FieldOutcome> outcomes = f.bridge.apply(c);
    bool refused = false;
    for (const FieldOutcome& o : outcomes) {
      if (o.field != k.field) {
        EXPECT_TRUE(o.applied) << o.field << ": " << o.why;
        continue;
      }
      refused = !o.applied;
      EXPECT_NE(o.why.find(k.why), std::string::npos)
          << "expected '" << k.why << "', got '" << o.why << "'";
    }
    EXPECT_TRUE(refused);
    // The request now holds the value in use, which the server reports back.
    const ClothSimConfig now = f.bridge.current();
    EXPECT_EQ(c.bending_stiffness, now.bending_stiffness);
    EXPECT_EQ(c.structural_stiffness, now.structural_stiffness);
    EXPECT_EQ(c.shear_stiffness, now.shear_stiffness);
    EXPECT_EQ(c.solver, now.solver);
    EXPECT_EQ(c.color_mode, now.color_mode);
    EXPECT_EQ(c.iterations, now.iterations);
    EXPECT_EQ(c.substeps, now.substeps);
    EXPECT_EQ(c.budget_ms, now.budget_ms);
    EXPECT_EQ(now.structural_stiffness, before.structural_stiffness);
    EXPECT_EQ(now.solver, before.solver);
    EXPECT_EQ(now.damping, k.field == std::string("damping") ? before.damping : 1.5);
  }
}

TEST(ReconfigureBridge, FrameBudgetForIsOffAtZeroAndKeepsWithinTheFrame) {
  const double frame = 1.0 / 60.0;
  EXPECT_FALSE(frameBudgetFor(0.0, frame).has_value());
  const std::optional<FrameBudget> b = frameBudgetFor(0.3, frame);
  ASSERT_TRUE(b.has_value());
  EXPECT_DOUBLE_EQ(b->budget(), 3e-4);
  EXPECT_TRUE(frameBudgetFor(1e3 * frame, frame).has_value());  // the whole frame
  EXPECT_THROW(frameBudgetFor(-1.0, frame), std::invalid_argument);
  EXPECT_THROW(frameBudgetFor(1e4, frame), std::invalid_argument);
  // Above the frame: it let the substeps grow to 259 at 100 ms (0.26x real time).
  try {
    frameBudgetFor(100.0, frame, "parameter '~budget_ms':");
    ADD_FAILURE() << "100 ms on a 16.7 ms frame accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("parameter '~budget_ms': 100 must be at most the frame, "
                                         "16.667 ms"),
              std::string::npos)
        << e.what();
  }
}

TEST(ReconfigureBridge, ABudgetAboveTheFrameIsRefusedAndTheValueInUseReported) {
  Fixture f;
  ClothSimConfig c = f.bridge.current();
  c.budget_ms = 100.0;
  const std::vector<FieldOutcome> outcomes = f.bridge.apply(c);
  ASSERT_EQ(outcomes.size(), 1u);
  EXPECT_FALSE(outcomes[0].applied);
  EXPECT_NE(outcomes[0].why.find("budget_ms 100 must be at most the frame"), std::string::npos)
      << outcomes[0].why;
  EXPECT_EQ(c.budget_ms, 0.0);
  EXPECT_FALSE(f.budget.has_value());
}

TEST(ReconfigureBridge, TurningTheBudgetOffRestoresTheConfiguredSubsteps) {
  Fixture f;
  ClothSimConfig c = f.bridge.current();
  c.substeps = 4;
  f.bridge.apply(c);
  c = f.bridge.current();
  c.budget_ms = 5.0;
  for (const FieldOutcome& o : f.bridge.apply(c)) EXPECT_TRUE(o.applied) << o.why;
  // The node's budget picks 259 substeps (as the node's adaptSubsteps does).
  SolverSettings chosen = f.sim.solverSettings();
  chosen.substeps = 259;
  f.sim.setSolverSettings(chosen);
  EXPECT_EQ(f.bridge.configuredSubsteps(), 4);
  c = f.bridge.current();
  EXPECT_EQ(c.substeps, 259);
  c.budget_ms = 0.0;
  for (const FieldOutcome& o : f.bridge.apply(c)) EXPECT_TRUE(o.applied) << o.why;
  EXPECT_FALSE(f.budget.has_value());
  EXPECT_EQ(f.sim.solverSettings().substeps, 4) << "the budget's last choice was left in place";
  EXPECT_EQ(f.sim.substeps(), 4);
  EXPECT_EQ(f.bridge.current().substeps, 4);

  // With automatic substeps the budget limits the controller; off gives it its own cap back.
  c = f.bridge.current();
  c.error_tolerance = 1e-4;  // first: substeps 0 needs a tolerance (applied after substeps)
  for (const FieldOutcome& o : f.bridge.apply(c)) EXPECT_TRUE(o.applied) << o.why;
  c = f.bridge.current();
  c.substeps = 0;
  c.budget_ms = 5.0;
  for (const FieldOutcome& o : f.bridge.apply(c)) EXPECT_TRUE(o.applied) << o.why;
  f.sim.setSubstepLimit(3);
  ASSERT_EQ(f.sim.substepLimit(), 3);
  c = f.bridge.current();
  c.budget_ms = 0.0;
  for (const FieldOutcome& o : f.bridge.apply(c)) EXPECT_TRUE(o.applied) << o.why;
  EXPECT_EQ(f.sim.substepLimit(), Simulation::kMaxAutomaticSubsteps);
  EXPECT_TRUE(f.sim.solverSettings().automaticSubsteps());
}

}  // namespace
}  // namespace cloth_sim::node
