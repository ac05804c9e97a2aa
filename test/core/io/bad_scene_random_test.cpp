// Randomized bad input to the scene reader and builder: every scalar field of a small scene
// (grid, material, pins, a sphere, the ground, the solver block) gets NaN, infinities, huge and
// tiny finite values, wrong types or a long string, one field per case. Each case must either
// be refused with a message naming the field, or be accepted and then simulated with no
// rolled-back frame, no non-finite number, and every pin and sphere of the scene still there.
// The seeds are fixed and printed; CLOTH_SIM_BAD_SCENE_SEED and _CASES run others.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "cloth_sim/core/io/scene.h"

namespace cloth_sim {
namespace {

/// A small horizontal cloth pinned at two corners, a still sphere under it and the ground:
/// every field the reader knows, each scalar a {placeholder}.
const char* const kTemplate = R"(name: random_base
time_step: {time_step}
gravity: [{gravity_x}, 0, -9.81]
divergence_strain: {divergence_strain}
solver:
  name: {solver}
  iterations: {iterations}
  substeps: {substeps}
  tolerance: {tolerance}
  integrator: {integrator}
  chebyshev: {rho: {rho}, gamma: {gamma}, delay: {delay}}
  anderson: {window: {anderson_window}}
  lbfgs: {window: {lbfgs_window}}
cloth:
  grid:
    rows: {rows}
    cols: {cols}
    size: [{width}, {height}]
    position: [{position_x}, 0, 1]
    orientation_rpy: [{roll}, 0, 0]
material:
  areal_density: {areal_density}
  damping: {damping}
  springs: {structural: {structural}, shear: {shear}, bending: {bending}}
  shear_pattern: {shear_pattern}
pins:
  - {row: {pin_row}, col: 0}
  - {vertex: {pin_vertex}, target: [{target_x}, 0.5, 1], stiffness: {pin_stiffness}}
colliders:
  spheres:
    - {center: [{center_x}, 0, 0.7], radius: {radius}, velocity: [0, {velocity_y}, 0], friction: {sphere_friction}, mass: {mass}, restitution: {restitution}}
  ground: {height: {ground_height}, friction: {ground_friction}}
)";

/// One placeholder: its value in the base scene and what a refusal must name (the field's path
/// and, where the message names the entry only, the key).
struct Field {
  const char* placeholder;
  const char* base;
  const char* path;  ///< must appear in the message
  const char* key;   ///< must appear too ("" = nothing more)
  /// Moving the cloth moves what the pin target, the sphere and the ground are measured
  /// against: its refusal may name the field it now conflicts with instead (any of these).
  std::vector<const char*> instead = {};
};

const std::vector<Field> kFields = {
    {"time_step", "1/60", "time_step", ""},
    {"gravity_x", "0", "gravity[0]", ""},
    {"divergence_strain", "100", "divergence_strain", ""},
    {"solver", "local_global", "solver.name", ""},
    {"iterations", "4", "solver.iterations", ""},
    {"substeps", "2", "solver.substeps", ""},
    {"tolerance", "0", "solver.tolerance", ""},
    {"integrator", "implicit_euler", "solver.integrator", ""},
    {"rho", "0", "solver.chebyshev.rho", ""},
    {"gamma", "1", "solver.chebyshev.gamma", ""},
    {"delay", "3", "solver.chebyshev.delay", ""},
    {"anderson_window", "5", "solver.anderson.window", ""},
    {"lbfgs_window", "5", "solver.lbfgs.window", ""},
    {"rows", "8", "cloth.grid.rows", ""},
    {"cols", "8", "cloth.grid.cols", ""},
    {"width", "1", "cloth.grid.size", ""},
    {"height", "1", "cloth.grid.size", ""},
    {"position_x", "0", "cloth.grid.position", "", {"pins[1].target", "colliders.spheres[0]"}},
    {"roll", "0", "cloth.grid.orientation_rpy", "",
     {"pins[1].target", "colliders.spheres[0]", "colliders.ground.height"}},
    {"areal_density", "0.1", "material.areal_density", ""},
    {"damping", "0.1", "material.damping", ""},
    {"structural", "1000", "material.springs.structural", ""},
    {"shear", "1000", "material.springs.shear", ""},
    {"bending", "10", "material.springs.bending", ""},
    {"shear_pattern", "both", "material.shear_pattern", ""},
    {"pin_row", "0", "pins[0]", "row"},
    {"pin_vertex", "7", "pins[1]", "vertex"},
    {"target_x", "0.5", "pins[1].target", ""},
    {"pin_stiffness", "0", "pins[1].stiffness", ""},
    {"center_x", "0", "colliders.spheres[0]", "center"},
    {"radius", "0.1", "colliders.spheres[0]", "radius"},
    {"velocity_y", "0", "colliders.spheres[0]", "velocity"},
    {"sphere_friction", "0.1", "colliders.spheres[0]", "friction"},
    {"mass", "0", "colliders.spheres[0]", "mass"},
    {"restitution", "0", "colliders.spheres[0]", "restitution"},
    {"ground_height", "0", "colliders.ground.height", ""},
    {"ground_friction", "0", "colliders.ground.friction", ""},
};

/// The values tried: NaN and infinities in YAML's and C's spellings, the largest and smallest
/// doubles, huge and tiny finite numbers, integers past int, wrong types, a long string.
std::vector<std::string> fixedValues() {
  return {".nan", "nan", "NaN", ".inf", "-.inf", "inf", "-inf", "1/0", "0/0", "1e308",
          "-1e308", "1.7976931348623157e308", "1e300", "-1e300", "1e30", "1e9", "1e6", "-1e6",
          "1e-300", "-1e-300", "5e-324", "1e-9", "0", "-0", "-1", "0.5", "2", "3", "2147483648",
          "-2147483649", "99999999999999999999", "1e3", "0x10", "abc", "\"\"", "~", "true",
          "[1, 2]", "{a: 1}", "[]", std::string(5000, 'x'), "1e", "1/60/2"};
}

/// A random number: sign, and magnitude 10^U(-320, 310) (so sometimes 0 or inf), as text.
std::string randomNumber(std::mt19937& rng) {
  std::uniform_real_distribution<double> exponent(-320.0, 310.0), coin(0.0, 1.0);
  const double v = (coin(rng) < 0.5 ? -1.0 : 1.0) * std::pow(10.0, exponent(rng));
  char text[64];
  std::snprintf(text, sizeof text, "%.17g", v);
  return text;
}

std::string scene(const std::string& placeholder, const std::string& value) {
  std::string text = kTemplate;
  for (const Field& f : kFields) {
    const std::string key = "{" + std::string(f.placeholder) + "}";
    const std::string with = f.placeholder == placeholder ? value : f.base;
    for (std::size_t at = text.find(key); at != std::string::npos; at = text.find(key, at)) {
      text.replace(at, key.size(), with);
      at += with.size();
    }
  }
  return text;
}

struct Outcome {
  int refused = 0, accepted = 0;
};

/// Runs @p count cases from @p seed; every failure names the seed, the case, field and value.
Outcome runCases(unsigned seed, int count) {
  std::mt19937 rng(seed);
  const std::vector<std::string> fixed = fixedValues();
  std::uniform_int_distribution<std::size_t> pick_field(0, kFields.size() - 1),
      pick_fixed(0, fixed.size() - 1);
  std::uniform_real_distribution<double> coin(0.0, 1.0);
  Outcome out;
  for (int k = 0; k < count; ++k) {
    const Field& field = kFields[pick_field(rng)];
    const std::string value = coin(rng) < 0.7 ? fixed[pick_fixed(rng)] : randomNumber(rng);
    SCOPED_TRACE("seed " + std::to_string(seed) + " case " + std::to_string(k) + ": " +
                 field.placeholder + " = " + value.substr(0, 40));
    std::optional<Simulation> sim;
    try {
      sim.emplace(makeSimulation(parseScene(scene(field.placeholder, value), "random.yaml")));
    } catch (const std::exception& e) {
      const std::string message = e.what();
      ++out.refused;
      bool named = message.find(field.path) != std::string::npos &&
                   message.find(field.key) != std::string::npos;
      for (const char* other : field.instead) named = named || message.find(other) != std::string::npos;
      EXPECT_TRUE(named) << "names neither " << field.path << " nor a field it conflicts with: "
                         << message.substr(0, 300);
      EXPECT_LT(message.size(), 1000u) << "a long value must not be echoed whole";
      continue;
    }
    ++out.accepted;
    const std::size_t pins = sim->pins().size(), spheres = sim->colliders().spheres().size();
    for (int frame = 0; frame < 3; ++frame) {
      const StepReport report = sim->step();
      EXPECT_EQ(report.status, StepStatus::kOk) << report.message;
      EXPECT_TRUE(sim->state().allFinite());
      EXPECT_FALSE(std::isnan(sim->totalEnergy()));
      if (report.status != StepStatus::kOk) break;
    }
    EXPECT_EQ(sim->pins().size(), pins);
    EXPECT_EQ(sim->colliders().spheres().size(), spheres);
  }
  return out;
}

TEST(BadSceneRandom, EveryFieldRefusedByNameOrSimulatedCleanly) {
  const char* seed_env = std::getenv("CLOTH_SIM_BAD_SCENE_SEED");
  const char* cases_env = std::getenv("CLOTH_SIM_BAD_SCENE_CASES");
  const std::vector<unsigned> seeds =
      seed_env ? std::vector<unsigned>{static_cast<unsigned>(std::atol(seed_env))}
               : std::vector<unsigned>{1, 2, 3, 4};
  const int per_seed = cases_env ? std::atoi(cases_env) : 150;
  Outcome total;
  for (unsigned seed : seeds) {
    const Outcome o = runCases(seed, per_seed);
    std::printf("[measured] seed %u: %d cases, %d refused by name, %d accepted and simulated\n",
                seed, per_seed, o.refused, o.accepted);
    total.refused += o.refused;
    total.accepted += o.accepted;
  }
  EXPECT_GE(total.refused + total.accepted, 500);
  EXPECT_GT(total.accepted, 0);  // the base scene and harmless values do run
}

TEST(BadSceneRandom, TheBaseSceneRuns) {
  Simulation sim = makeSimulation(parseScene(scene("", ""), "base.yaml"));
  for (int frame = 0; frame < 30; ++frame) ASSERT_EQ(sim.step().status, StepStatus::kOk);
}

}  // namespace
}  // namespace cloth_sim
