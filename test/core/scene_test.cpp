#include <dirent.h>

#include <gtest/gtest.h>

#include "cloth_sim/core/scene.h"
#include "test_util.h"

namespace cloth_sim {
namespace {

std::vector<std::string> shippedScenes() {
  std::vector<std::string> out;
  const std::string dir = test::sourcePath("config/scenes");
  DIR* d = opendir(dir.c_str());
  if (d == nullptr) return out;
  while (dirent* e = readdir(d)) {
    const std::string name = e->d_name;
    if (name.size() > 5 && name.substr(name.size() - 5) == ".yaml") out.push_back(dir + "/" + name);
  }
  closedir(d);
  return out;
}

TEST(Scene, EveryShippedSceneLoadsAndSteps) {
  const auto scenes = shippedScenes();
  ASSERT_GE(scenes.size(), 4u);
  for (const std::string& path : scenes) {
    SCOPED_TRACE(path);
    const SceneConfig config = loadSceneFile(path);
    Simulation sim = makeSimulation(config);
    EXPECT_EQ(sim.step().status, StepStatus::kOk);
    EXPECT_TRUE(sim.state().allFinite());
  }
}

TEST(Scene, RequiredScenesDeclareOnlyWhatTheyUse) {
  const auto load = [](const std::string& n) {
    return loadSceneFile(test::sourcePath("config/scenes/" + n + ".yaml"));
  };
  const SceneConfig hanging = load("hanging"), drape = load("drape"), trampoline = load("trampoline"),
                    stiff = load("stiff");
  EXPECT_EQ(hanging.name, "hanging");
  EXPECT_EQ(hanging.pins.size(), 2u);
  EXPECT_TRUE(hanging.spheres.empty());
  EXPECT_FALSE(hanging.ground.enabled);
  EXPECT_EQ(drape.spheres.size(), 1u);
  EXPECT_TRUE(drape.ground.enabled);
  EXPECT_TRUE(drape.pins.empty());
  EXPECT_EQ(trampoline.pins.size(), static_cast<std::size_t>(4 * (trampoline.grid.rows - 1)));
  EXPECT_EQ(trampoline.spheres.size(), 1u);
  EXPECT_FALSE(trampoline.grid.has_bending);
  EXPECT_DOUBLE_EQ(stiff.grid.structural, 100.0 * hanging.grid.structural);
  EXPECT_DOUBLE_EQ(stiff.grid.shear, 100.0 * hanging.grid.shear);
  EXPECT_DOUBLE_EQ(stiff.grid.bending, 100.0 * hanging.grid.bending);
  EXPECT_NEAR(hanging.time_step, 1.0 / 60.0, 1e-15);  // written "1/60"
}

const char* kValid = R"(
time_step: 0.01
cloth:
  grid: {rows: 4, cols: 5, size: [1.0, 0.5]}
material:
  springs: {structural: 100}
)";

TEST(Scene, MinimalSceneHasDocumentedDefaults) {
  const SceneConfig s = parseScene(kValid, "minimal");
  EXPECT_EQ(s.grid.rows, 4);
  EXPECT_EQ(s.grid.cols, 5);
  EXPECT_FALSE(s.grid.has_shear);
  EXPECT_FALSE(s.grid.has_bending);
  EXPECT_EQ(s.options.solver, "local_global");
  EXPECT_EQ(s.gravity, Vec3(0, 0, -9.81));
  EXPECT_EQ(s.damping, 0.0);
  EXPECT_TRUE(s.pins.empty());
}

struct Malformed {
  const char* yaml;
  const char* field;     // the field the error must name
  const char* fragment;  // and a piece of its message
};

TEST(Scene, MalformedScenesAreRefusedNamingTheField) {
  const std::vector<Malformed> cases = {
      {"cloth:\n  grid: {rows: -3, cols: 5, size: [1, 1]}\nmaterial: {springs: {structural: 1}}",
       "cloth.grid.rows", "value -3 must be an integer in [2, 2000]"},
      {"cloth:\n  grid: {rowz: 3, rows: 3, cols: 5, size: [1, 1]}\nmaterial: {springs: {structural: 1}}",
       "cloth.grid.rowz", "unknown field"},
      {"cloth:\n  grid: {rows: 3, cols: 3, size: [1, 0]}\nmaterial: {springs: {structural: 1}}",
       "cloth.grid.size[1]", "> 0"},
      {"cloth:\n  grid: {rows: 3, cols: 3, size: [1, 1]}\nmaterial: {springs: {structural: -1}}",
       "material.springs.structural", ">= 0 N/m"},
      {"cloth:\n  grid: {rows: 3, cols: 3, size: [1, 1]}\nmaterial: {springs: {}}",
       "material.springs", "at least one family"},
      {"cloth:\n  grid: {rows: 3, cols: 3, size: [1, 1]}\nmaterial: {damping: fast, springs: {shear: 1}}",
       "material.damping", "'fast' must be a number"},
      {"time_step: -0.1\ncloth:\n  grid: {rows: 3, cols: 3, size: [1, 1]}\nmaterial: {springs: {shear: 1}}",
       "time_step", "in (0, 1] s"},
      {"solver: {name: rk4}\ncloth:\n  grid: {rows: 3, cols: 3, size: [1, 1]}\nmaterial: {springs: {shear: 1}}",
       "solver.name", "unknown solver 'rk4'"},
      {"solver: {iterations: 0}\ncloth:\n  grid: {rows: 3, cols: 3, size: [1, 1]}\nmaterial: {springs: {shear: 1}}",
       "solver.iterations", "[1, 100000]"},
      {"cloth:\n  grid: {rows: 3, cols: 3, size: [1, 1]}\nmaterial: {springs: {shear: 1}}\npins: [{row: 3, col: 0}]",
       "pins[0].row", "[0, 2]"},
      {"cloth:\n  grid: {rows: 3, cols: 3, size: [1, 1]}\nmaterial: {springs: {shear: 1}}\npins: [{vertex: 1}, {row: 0, col: 1}]",
       "pins[1]", "already pinned"},
      {"cloth:\n  grid: {rows: 3, cols: 3, size: [1, 1]}\nmaterial: {springs: {shear: 1}}\npins: [{edge: middle}]",
       "pins[0].edge", "top, bottom, left, right or all"},
      {"cloth:\n  grid: {rows: 3, cols: 3, size: [1, 1]}\nmaterial: {springs: {shear: 1}}\npins: [{vertex: 0, target: [1, 2]}]",
       "pins[0].target", "list of 3 numbers"},
      {"cloth:\n  grid: {rows: 3, cols: 3, size: [1, 1]}\nmaterial: {springs: {shear: 1}}\ncolliders: {spheres: [{center: [0, 0, 0], radius: 0}]}",
       "colliders.spheres[0].radius", "> 0 m"},
      {"cloth:\n  grid: {rows: 3, cols: 3, size: [1, 1]}\nmaterial: {springs: {shear: 1}}\ncolliders: {ground: {friction: -1}}",
       "colliders.ground.friction", ">= 0"},
      {"cloth:\n  grid: {rows: 3, cols: 3, size: [1, 1]}\nmaterial: {springs: {shear: 1}}\ngravity: [0, 0, .nan]",
       "gravity[2]", "finite"},
      {"material: {springs: {shear: 1}}", "cloth", "is required"},
      {"cloth:\n  grid: {rows: 3, cols: 3, size: [1, 1]}", "material", "is required"},
  };
  for (const Malformed& c : cases) {
    try {
      parseScene(c.yaml, "bad.yaml");
      ADD_FAILURE() << "accepted: " << c.yaml;
    } catch (const SceneError& e) {
      EXPECT_EQ(e.field(), c.field) << e.what();
      EXPECT_NE(std::string(e.what()).find(c.fragment), std::string::npos) << e.what();
      EXPECT_EQ(std::string(e.what()).rfind("bad.yaml: field '" + std::string(c.field) + "'", 0), 0u)
          << e.what();
    }
  }
}

TEST(Scene, SyntaxErrorsAndMissingFilesAreReported) {
  try {
    parseScene("cloth: [unclosed", "broken.yaml");
    FAIL();
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("YAML syntax error"), std::string::npos) << e.what();
  }
  EXPECT_THROW(loadSceneFile("/nonexistent/scene.yaml"), SceneError);
}

TEST(Scene, EdgePinsCoverTheBorderOnce) {
  const std::string yaml = std::string(kValid) + "pins: [{edge: top}, {edge: left, stiffness: 20}]\n";
  const SceneConfig s = parseScene(yaml, "edges");
  EXPECT_EQ(s.pins.size(), 5u + 3u);  // top row (5) + left column without the shared corner (3)
  EXPECT_EQ(s.pins[0].stiffness, 0.0);
  EXPECT_EQ(s.pins.back().stiffness, 20.0);
}

}  // namespace
}  // namespace cloth_sim
