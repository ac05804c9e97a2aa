// The solver registry: its data file (read by cfg/ClothSim.cfg), each entry's own settings, and
// each entry's capabilities against what its solver's step does.
#include <set>
#include <string>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include "cloth_sim/core/collision/contact_forces.h"
#include "cloth_sim/core/solvers/registry.h"
#include "test_util.h"

namespace cloth_sim {
namespace {

TEST(SolverRegistry, TheDataFileListsTheRegistryInOrder) {
  const YAML::Node file = YAML::LoadFile(test::sourcePath("src/core/solvers/registry.yaml"));
  ASSERT_TRUE(file.IsSequence());
  ASSERT_EQ(file.size(), solverRegistry().size());
  for (std::size_t k = 0; k < file.size(); ++k) {
    EXPECT_EQ(file[k]["name"].as<std::string>(), solverRegistry()[k].name);
    EXPECT_EQ(file[k]["description"].as<std::string>(), solverRegistry()[k].description);
  }
}

TEST(SolverRegistry, EachSolversOwnSettingsAreNamedAfterItAndDefaultToAnAllowedValue) {
  for (const SolverEntry& entry : solverRegistry()) {
    SCOPED_TRACE(entry.name);
    EXPECT_STREQ(makeSolver(entry.name)->name(), entry.name);
    EXPECT_EQ(findSolver(entry.name), &entry);
    std::set<std::string> fields;
    for (const SolverParam* param : entry.params) {
      EXPECT_EQ(std::string(param->name),
                "solver." + std::string(entry.name) + "." + param->field());
      EXPECT_TRUE(fields.insert(param->field()).second) << param->field();
      EXPECT_TRUE(param->allows(param->default_value)) << param->name;
      EXPECT_STREQ(param->param, "") << "a solver's own setting is not a node parameter";
    }
  }
  EXPECT_EQ(findSolver("rk4"), nullptr);
  EXPECT_THROW(solverEntry("rk4"), std::invalid_argument);
}

TEST(SolverParams, UnsetReadsTheDefaultAndSetValuesAreValidated) {
  const SolverEntry& anderson = solverEntry("anderson");
  ASSERT_EQ(anderson.params.size(), 1u);
  const SolverParam& window = *anderson.params.front();
  SolverSettings s;
  EXPECT_EQ(s.params.integer(window), static_cast<int>(window.default_value));
  s.params.set(window, 7);
  s.params.set(window, 8);  // replaces
  EXPECT_EQ(s.params.integer(window), 8);
  EXPECT_NO_THROW(s.validate());
  s.params.set(window, 0);
  EXPECT_THROW(s.validate(), std::invalid_argument);
}

/// A 6 x 6 cloth pinned at two corners, falling from rest: every solver is stable on it.
struct SmallCloth {
  BuiltObject object = test::makeGrid(6, 6, 400.0, 40.0, 4.0);
  PinSet pins;
  static constexpr double kStep = 1.0 / 240.0;  ///< s
  SmallCloth() {
    for (int v : {0, 5}) pins.add(v, object.rest_positions.col(v), 0.0, 36);
  }
  /// The state after @p steps steps of @p solver with @p settings from rest; the last step's
  /// result in @p last.
  State run(const std::string& solver, const SolverSettings& settings, int steps,
            SolveResult* last = nullptr) const {
    const std::unique_ptr<Solver> s = makeSolver(solver);
    State state = State::atRest(object.rest_positions);
    for (int k = 0; k < steps; ++k) {
      const SolveResult r = s->step({object.model, pins, kStep, 1}, settings, state);
      if (last != nullptr) *last = r;
    }
    return state;
  }
};

/// Whether @p solver refuses @p settings (Solver::requireSettings).
bool refuses(const std::string& solver, const SolverSettings& settings) {
  try {
    makeSolver(solver)->requireSettings(settings);
  } catch (const std::invalid_argument&) {
    return true;
  }
  return false;
}

TEST(SolverRegistry, CapabilitiesAreWhatEachStepDoes) {
  const SmallCloth cloth;
  for (const SolverEntry& entry : solverRegistry()) {
    SCOPED_TRACE(entry.name);
    const SolverCapabilities& can = entry.capabilities;
    SolverSettings base;
    base.max_iterations = 2;
    const State reference = cloth.run(entry.name, base, 3);

    SolverSettings more = base;
    more.max_iterations = 6;
    EXPECT_EQ(cloth.run(entry.name, more, 3).positions != reference.positions, can.iterations);

    // Iterations to spare: a tolerance that applies stops them early.
    SolverSettings many = base, loose = base;
    many.max_iterations = loose.max_iterations = 200;
    loose.tolerance = 0.5;
    if (refuses(entry.name, loose)) {
      EXPECT_FALSE(can.tolerance);
    } else {
      SolveResult all, stopped;
      cloth.run(entry.name, many, 1, &all);
      cloth.run(entry.name, loose, 1, &stopped);
      EXPECT_EQ(stopped.iterations < all.iterations, can.tolerance);
    }

    SolverSettings warm = base;
    warm.warm_start = true;
    if (refuses(entry.name, warm)) {
      EXPECT_FALSE(can.warm_start);
    } else {
      EXPECT_EQ(cloth.run(entry.name, warm, 3).positions != reference.positions, can.warm_start);
    }

    for (const Integrator integrator : kIntegrators) {
      if (integrator == SolverSettings{}.integrator) continue;
      SolverSettings other = base;
      other.integrator = integrator;
      EXPECT_EQ(!refuses(entry.name, other), can.supports(integrator))
          << integratorName(integrator);
      if (can.supports(integrator)) {  // honoured: another motion than implicit Euler's
        EXPECT_NE(cloth.run(entry.name, other, 3).positions, reference.positions);
      }
    }

    // Contacts given with the step: solved in it, or left to the projection after it.
    Colliders colliders;
    colliders.setGround({true, 0.99, 0.0});
    const std::vector<char> movable(36, 1);
    const Points start = cloth.object.rest_positions;
    ContactForces contacts;
    contacts.beginStep({SmallCloth::kStep, cloth.object.model.mass, movable, start},
                       colliders);
    State state = State::atRest(start);
    const SolveResult r =
        makeSolver(entry.name)->step({cloth.object.model, cloth.pins, SmallCloth::kStep, 1, &contacts}, base, state);
    EXPECT_EQ(r.used_contacts, can.contacts_in_step);
  }
}

}  // namespace
}  // namespace cloth_sim
