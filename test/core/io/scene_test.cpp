#include <dirent.h>

#include <tuple>

#include <gtest/gtest.h>

#include "cloth_sim/core/io/scene.h"
#include "cloth_sim/core/io/scene_builder.h"
#include "cloth_sim/core/solvers/registry.h"
#include "test_util.h"

namespace cloth_sim {
namespace {

/// The pins @p scene resolves to on its own cloth.
std::vector<PinSpec> pinsOf(const SceneConfig& scene) {
  return resolvePins(scene, buildCloth(scene).rest_positions);
}

/// Reads @p yaml and builds it: the reader's errors and the builder's (pin indices) alike.
void readAndBuild(const std::string& yaml) { makeSimulation(parseScene(yaml, "bad.yaml")); }

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
  EXPECT_EQ(pinsOf(trampoline).size(), static_cast<std::size_t>(4 * (trampoline.grid.rows - 1)));
  EXPECT_EQ(trampoline.spheres.size(), 1u);
  EXPECT_FALSE(trampoline.grid.material.has_bending);
  EXPECT_DOUBLE_EQ(stiff.grid.material.structural, 100.0 * hanging.grid.material.structural);
  EXPECT_DOUBLE_EQ(stiff.grid.material.shear, 100.0 * hanging.grid.material.shear);
  EXPECT_DOUBLE_EQ(stiff.grid.material.bending, 100.0 * hanging.grid.material.bending);
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
  EXPECT_FALSE(s.grid.material.has_shear);
  EXPECT_FALSE(s.grid.material.has_bending);
  EXPECT_EQ(s.options.solver, "local_global");
  // Solver fields it does not give are chosen for its solver when it is built: error control.
  EXPECT_FALSE(s.given.substeps || s.given.iterations || s.given.integrator ||
               s.given.error_tolerance);
  const SolverSettings built = resolveSolverDefaults(s, 2.0);
  EXPECT_EQ(built.substeps, 0);
  EXPECT_EQ(built.integrator, Integrator::kBdf2);
  EXPECT_EQ(built.max_iterations, kDefaultIterationCap);
  EXPECT_DOUBLE_EQ(built.error_tolerance, 2.0 * kDefaultRelativeErrorTolerance);
  // A solver without a convergence test keeps fixed substeps and iterations.
  SceneConfig explicit_scene = s;
  explicit_scene.options.solver = "verlet";
  const SolverSettings fixed = resolveSolverDefaults(explicit_scene, 2.0);
  EXPECT_EQ(fixed.substeps, 8);
  EXPECT_EQ(fixed.max_iterations, 2);
  EXPECT_EQ(fixed.error_tolerance, 0.0);
  // A scene that fixes its iterations or substeps keeps a fixed configuration ...
  const SceneConfig counted = parseScene(
      "solver: {substeps: 4}\ncloth:\n  grid: {rows: 3, cols: 3, size: [1, 1]}\n"
      "material: {springs: {shear: 1}}", "counted");
  const SolverSettings kept = resolveSolverDefaults(counted, 2.0);
  EXPECT_EQ(kept.substeps, 4);
  EXPECT_EQ(kept.max_iterations, 2);
  EXPECT_EQ(kept.integrator, Integrator::kImplicitEuler);
  EXPECT_EQ(kept.error_tolerance, 0.0);
  // ... substeps 0 asks for error control ...
  SceneConfig automatic = counted;
  automatic.options.settings.substeps = 0;
  EXPECT_DOUBLE_EQ(resolveSolverDefaults(automatic, 2.0).error_tolerance,
                   2.0 * kDefaultRelativeErrorTolerance);
  // ... and error_tolerance 0 means fixed substeps and iterations too.
  const SceneConfig fixed_scene = parseScene(
      "solver: {error_tolerance: 0, iterations: 5}\ncloth:\n  grid: {rows: 3, cols: 3, size: [1, 1]}\n"
      "material: {springs: {shear: 1}}", "fixed");
  const SolverSettings given = resolveSolverDefaults(fixed_scene, 2.0);
  EXPECT_EQ(given.substeps, 8);
  EXPECT_EQ(given.max_iterations, 5);
  EXPECT_EQ(given.error_tolerance, 0.0);
  EXPECT_EQ(s.gravity, Vec3(0, 0, -9.81));
  EXPECT_EQ(s.damping, 0.0);
  EXPECT_TRUE(s.pins.empty());
  EXPECT_FALSE(s.options.self_contact.enabled);  // off unless a scene asks
}

TEST(Scene, SelfCollisionIsOnWhenDeclaredWithItsThicknessAndFriction) {
  const std::string base = kValid;
  SceneConfig s = parseScene(base + "self_collision: {thickness: 0.02, friction: 0.4}\n", "on");
  EXPECT_TRUE(s.options.self_contact.enabled);
  EXPECT_EQ(s.options.self_contact.thickness, 0.02);
  EXPECT_EQ(s.options.self_contact.friction, 0.4);
  s = parseScene(base + "self_collision: {}\n", "defaults");
  EXPECT_TRUE(s.options.self_contact.enabled);
  EXPECT_EQ(s.options.self_contact.thickness, 0.0);  // automatic
  EXPECT_EQ(s.options.self_contact.friction, SelfContactSettings{}.friction);
  s = parseScene(base + "self_collision: {enabled: false, thickness: 0.02}\n", "off");
  EXPECT_FALSE(s.options.self_contact.enabled);
  Simulation sim = makeSimulation(s);
  EXPECT_EQ(sim.selfContact(), nullptr);
  const SceneConfig fold = loadSceneFile(test::sourcePath("config/scenes/fold.yaml"));
  EXPECT_EQ(fold.options.self_contact.thickness, 0.035);
  EXPECT_EQ(fold.pins.size(), 1u);
  EXPECT_TRUE(fold.ground.enabled);
  EXPECT_TRUE(loadSceneFile(test::sourcePath("config/scenes/pile.yaml")).pins.empty());
}

struct Malformed {
  std::string yaml;
  const char* field;     // the field the error must name
  const char* fragment;  // and a piece of its message
};

TEST(Scene, MalformedScenesAreRefusedNamingTheField) {
  const std::vector<Malformed> cases = {
      {"cloth:\n  grid: {rows: -3, cols: 5, size: [1, 1]}\nmaterial: {springs: {structural: 1}}",
       "cloth.grid.rows", "value -3 must be in [2, 2000]"},
      {"cloth:\n  grid: {rowz: 3, rows: 3, cols: 5, size: [1, 1]}\nmaterial: {springs: {structural: 1}}",
       "cloth.grid.rowz", "unknown field"},
      {"cloth:\n  grid: {rows: 3, cols: 3, size: [1, 0]}\nmaterial: {springs: {structural: 1}}",
       "cloth.grid.size[1]", "in [0.001, 10000] m"},
      {"cloth:\n  grid: {rows: 3, cols: 3, size: [1, 1]}\nmaterial: {springs: {structural: -1}}",
       "material.springs.structural", "in [0, 1e+09] N/m"},
      {"cloth:\n  grid: {rows: 3, cols: 3, size: [1, 1]}\nmaterial: {springs: {}}",
       "material.springs", "at least one family"},
      {"cloth:\n  grid: {rows: 3, cols: 3, size: [1, 1]}\nmaterial: {damping: fast, springs: {shear: 1}}",
       "material.damping", "'fast' must be a number"},
      {"time_step: -0.1\ncloth:\n  grid: {rows: 3, cols: 3, size: [1, 1]}\nmaterial: {springs: {shear: 1}}",
       "time_step", "in [1e-06, 1] s"},
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
       "colliders.spheres[0].radius", "in (0, 1e+06] m"},
      {"cloth:\n  grid: {rows: 3, cols: 3, size: [1, 1]}\nmaterial: {springs: {shear: 1}}\ncolliders: {ground: {friction: -1}}",
       "colliders.ground.friction", "in [0, 100]"},
      {"cloth:\n  grid: {rows: 3, cols: 3, size: [1, 1]}\nmaterial: {springs: {shear: 1}}\ngravity: [0, 0, .nan]",
       "gravity[2]", "finite"},
      {"material: {springs: {shear: 1}}", "cloth", "is required"},
      {"cloth:\n  grid: {rows: 3, cols: 3, size: [1, 1]}\nmaterial: {springs: {shear: 1}}\nself_collision: {thickness: -0.01}",
       "self_collision.thickness", ">= 0 m (0 = the mean rest edge length)"},
      {"cloth:\n  grid: {rows: 3, cols: 3, size: [1, 1]}\nmaterial: {springs: {shear: 1}}\nself_collision: {friction: -1}",
       "self_collision.friction", ">= 0"},
      {"cloth:\n  grid: {rows: 3, cols: 3, size: [1, 1]}\nmaterial: {springs: {shear: 1}}\nself_collision: {enabled: maybe}",
       "self_collision.enabled", "true or false"},
      {"cloth:\n  grid: {rows: 3, cols: 3, size: [1, 1]}\nmaterial: {springs: {shear: 1}}\nself_collision: {margin: 1}",
       "self_collision.margin", "unknown field"},
      // Sizes and positions whose derived masses or lengths overflow or lose precision,
      // and what the cloth cannot follow (scene_limits.h), name the field and the rule.
      {"cloth:\n  grid: {rows: 3, cols: 3, size: [1e308, 1e308]}\nmaterial: {springs: {shear: 1}}",
       "cloth.grid.size[0]", "value 1e+308 must be in [0.001, 10000] m"},
      {"cloth:\n  grid: {rows: 3, cols: 3, size: [1, 1], position: [1e300, 0, 0]}\nmaterial: {springs: {shear: 1}}",
       "cloth.grid.position[0]", "value 1e+300 must be in [-1e+06, 1e+06] m"},
      {"cloth:\n  grid: {rows: 2000, cols: 2, size: [0.001, 0.001], position: [1e6, 0, 0]}\nmaterial: {springs: {shear: 1}}",
       "cloth.grid.position", "rest lengths would lose their precision"},
      {"cloth:\n  grid: {rows: 3, cols: 3, size: [1, 1]}\nmaterial: {springs: {shear: 1}}\npins: [{vertex: 0, target: [1e6, 0, 0]}]",
       "pins[0].target", "beyond ~sphere_cull_distance = 20 m"},
      {"cloth:\n  grid: {rows: 3, cols: 3, size: [1, 1]}\nmaterial: {springs: {shear: 1}}\ncolliders: {spheres: [{center: [0, 0, 0], radius: 1e6}]}",
       "colliders.spheres[0]", "radius 1e+06 m must be at most the cloth's size, 1 m"},
      {"cloth:\n  grid: {rows: 3, cols: 3, size: [1, 1]}\nmaterial: {springs: {shear: 1}}\ncolliders: {spheres: [{center: [0, 0, 1], radius: 0.1, velocity: [1e9, 0, 0]}]}",
       "colliders.spheres[0]", "velocity (1e+09, 0, 0) m/s: its speed 1e+09 m/s must be at most its radius per implicit step"},
      {"cloth:\n  grid: {rows: 3, cols: 3, size: [1, 1]}\nmaterial: {springs: {shear: 1}}\ncolliders: {spheres: [{center: [0, 0, 1], radius: 0.1, mass: 1e6}]}",
       "colliders.spheres[0]", "mass 1e+06 kg must be at most 100 times the cloth's mass"},
      {"cloth:\n  grid: {rows: 3, cols: 3, size: [1, 1]}\nmaterial: {springs: {shear: 1}}\ncolliders: {ground: {height: 5}}",
       "colliders.ground.height", "must be at most the cloth's lowest initial height, 0 m"},
      {"solver: {name: " + std::string(100000, 'x') + "}\ncloth:\n  grid: {rows: 3, cols: 3, size: [1, 1]}\nmaterial: {springs: {shear: 1}}",
       "solver.name", "... (100000 characters)' is too long for a name"},
      {"cloth:\n  grid: {rows: 3, cols: 3, size: [1, 1]}", "material", "is required"},
      {"solver: {substeps: -1}\ncloth:\n  grid: {rows: 3, cols: 3, size: [1, 1]}\nmaterial: {springs: {shear: 1}}",
       "solver.substeps", "[0, 1000]"},
      // YAML keys are unique: the second value was dropped without a word.
      {"time_step: 1/60\ncloth:\n  grid: {rows: 3, cols: 3, size: [1, 1]}\nmaterial: {springs: {shear: 1}}\ntime_step: 1/30",
       "time_step", "given twice (lines 1 and 5)"},
      {"cloth:\n  grid: {rows: 3, cols: 3, rows: 4, size: [1, 1]}\nmaterial: {springs: {shear: 1}}",
       "cloth.grid.rows", "given twice (lines 2 and 2)"},
      {"? [a, b]\n: 1\ncloth:\n  grid: {rows: 3, cols: 3, size: [1, 1]}\nmaterial: {springs: {shear: 1}}",
       "(top level)", "key [a, b] on line 1 must be a plain name"},
  };
  for (const Malformed& c : cases) {
    try {
      readAndBuild(c.yaml);
      ADD_FAILURE() << "accepted: " << c.yaml;
    } catch (const SceneError& e) {
      EXPECT_EQ(e.field(), c.field) << e.what();
      EXPECT_NE(std::string(e.what()).find(c.fragment), std::string::npos) << e.what();
      EXPECT_EQ(std::string(e.what()).rfind("bad.yaml: field '" + std::string(c.field) + "'", 0), 0u)
          << e.what();
    }
  }
}

std::string meshScene(const std::string& cloth_file, const std::string& extra) {
  return "cloth:\n  mesh: {file: " + test::sourcePath(cloth_file) +
         "}\nmaterial: {springs: {structural: 100}}\n" + extra;
}

TEST(Scene, MalformedMeshScenesAreRefusedNamingTheField) {
  const std::string quad = "test/data/quad.obj";
  const std::vector<std::tuple<std::string, std::string, std::string>> cases = {
      {"cloth:\n  grid: {rows: 3, cols: 3, size: [1, 1]}\n  mesh: {file: a.obj}\nmaterial: {springs: {shear: 1}}",
       "cloth", "exactly one of 'grid' or 'mesh'"},
      {"cloth:\n  mesh: {scale: 2}\nmaterial: {springs: {structural: 1}}", "cloth.mesh.file", "is required"},
      {meshScene(quad, "").replace(meshScene(quad, "").find("}"), 1, ", scale: 1e6, position: [1e6, 0, 0]}"),
       "cloth.mesh.scale", "out of the scene: its coordinate 2e+06 must be in [-1e+06, 1e+06] m"},
      {meshScene("test/data/missing.obj", ""), "cloth.mesh.file", "cannot open the OBJ file"},
      {meshScene("test/data/nonmanifold.obj", ""), "cloth.mesh.file", "non-manifold edge (0, 1)"},
      {meshScene("test/data/degenerate.obj", ""), "cloth.mesh.file", "triangle 1 (0, 1, 3) is degenerate"},
      {"cloth:\n  mesh: {file: " + test::sourcePath(quad) + "}\nmaterial: {springs: {structural: 1, shear: 2}}",
       "material.springs.shear", "a mesh cloth has springs on its edges"},
      {meshScene(quad, "pins: [{row: 0, col: 0}]"), "pins[0]", "need a grid cloth"},
      {meshScene(quad, "pins: [{vertex: 4}]"), "pins[0].vertex", "[0, 3]"},
      {meshScene(quad, "pins: [{region: {min: [5, 5, 5], max: [6, 6, 6]}}]"), "pins[0].region",
       "contains no vertex"},
      {meshScene(quad, "pins: [{region: {min: [1, 1, 1], max: [0, 0, 0]}}]"), "pins[0].region",
       "'min' must not exceed 'max'"},
      {meshScene(quad, "colliders: {meshes: [{file: " + test::sourcePath(quad) + ", thickness: 0}]}"),
       "colliders.meshes[0].thickness", "in (0, 1] m"},
      {meshScene(quad, "colliders: {meshes: [{file: " + test::sourcePath("test/data/degenerate.obj") + "}]}"),
       "colliders.meshes[0].file", "degenerate"},
  };
  for (const auto& [yaml, field, fragment] : cases) {
    try {
      readAndBuild(yaml);
      ADD_FAILURE() << "accepted: " << yaml;
    } catch (const SceneError& e) {
      EXPECT_EQ(e.field(), field) << e.what();
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
  }
}

TEST(Scene, MeshClothRegionPinsAndRelativeFiles) {
  // Files are found relative to the scene file: the shipped tablecloth uses ../meshes/.
  const SceneConfig table = loadSceneFile(test::sourcePath("config/scenes/tablecloth.yaml"));
  EXPECT_EQ(table.cloth_kind, SceneConfig::ClothKind::kMesh);
  EXPECT_EQ(table.mesh.mesh.vertexCount(), 1261);
  EXPECT_EQ(table.meshes.size(), 1u);
  EXPECT_NEAR(table.mesh.mesh.vertices(2, 0), 1.1, 1e-12);  // placed by cloth.mesh.position
  // A region pin takes every vertex in the box: the quad's two corners at x = 1.
  const SceneConfig q = parseScene(
      meshScene("test/data/quad.obj", "pins: [{region: {min: [0.9, -1, -1], max: [1.1, 2, 1]}, stiffness: 30}]"),
      "q.yaml");
  const std::vector<PinSpec> q_pins = pinsOf(q);
  ASSERT_EQ(q_pins.size(), 2u);
  EXPECT_EQ(q_pins[0].stiffness, 30.0);
  EXPECT_EQ(makeSimulation(q).pins().size(), 2u);
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

TEST(Scene, IntegratorIsReadAndAnUnknownNameListsTheValidOnes) {
  EXPECT_EQ(parseScene(kValid, "minimal").options.settings.integrator, Integrator::kImplicitEuler);
  const std::string scene = std::string(kValid) + "solver: {name: newton, integrator: bdf2}\n";
  EXPECT_EQ(parseScene(scene, "bdf2.yaml").options.settings.integrator, Integrator::kBdf2);
  try {
    parseScene(std::string(kValid) + "solver: {integrator: bdf3}\n", "bad.yaml");
    FAIL();
  } catch (const SceneError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("solver.integrator"), std::string::npos) << what;
    EXPECT_NE(what.find("implicit_euler, bdf2"), std::string::npos) << what;
  }
  // An explicit solver cannot integrate with BDF2: refused when the simulation is built.
  EXPECT_THROW(
      readAndBuild(std::string(kValid) + "solver: {name: verlet, integrator: bdf2}\n"),
      std::invalid_argument);
}

TEST(Scene, EdgePinsCoverTheBorderOnce) {
  const std::string yaml = std::string(kValid) + "pins: [{edge: top}, {edge: left, stiffness: 20}]\n";
  const std::vector<PinSpec> pins = pinsOf(parseScene(yaml, "edges"));
  EXPECT_EQ(pins.size(), 5u + 3u);  // top row (5) + left column without the shared corner (3)
  EXPECT_EQ(pins[0].stiffness, 0.0);
  EXPECT_EQ(pins.back().stiffness, 20.0);
}

TEST(Scene, TheReaderKeepsPinSelectorsAsData) {
  // Parsing resolves nothing: an out-of-range row is the builder's to refuse.
  const std::string yaml = std::string(kValid) +
                           "pins: [{row: 9, col: 1, target: [0, 0, 1]}, {edge: all, stiffness: 5}]\n";
  const SceneConfig s = parseScene(yaml, "selectors");
  ASSERT_EQ(s.pins.size(), 2u);
  EXPECT_EQ(s.pins[0].kind, PinSelector::Kind::kCell);
  EXPECT_EQ(s.pins[0].row, 9);
  EXPECT_EQ(s.pins[0].field, "pins[0]");
  EXPECT_EQ(s.pins[1].kind, PinSelector::Kind::kEdge);
  EXPECT_EQ(s.pins[1].edge, "all");
  try {
    makeSimulation(s);
    ADD_FAILURE() << "row 9 of 4 accepted";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.field(), "pins[0].row");
    EXPECT_STREQ(e.what(), "selectors: field 'pins[0].row': value 9 must be an integer in [0, 3]");
  }
}

TEST(Scene, SolverBlocksAreReadFromTheRegistry) {
  const SceneConfig s = parseScene(
      "solver: {chebyshev: {rho: 0.5, delay: 4}, lbfgs: {window: 9}}\n" + std::string(kValid),
      "blocks");
  const SolverEntry& chebyshev = solverEntry("chebyshev");
  ASSERT_EQ(chebyshev.params.size(), 3u);
  EXPECT_EQ(s.options.settings.params.number(*chebyshev.params[0]), 0.5);  // rho
  EXPECT_EQ(s.options.settings.params.number(*chebyshev.params[1]), 1.0);  // gamma: default
  EXPECT_EQ(s.options.settings.params.integer(*chebyshev.params[2]), 4);   // delay
  EXPECT_EQ(s.options.settings.params.integer(*solverEntry("lbfgs").params[0]), 9);
  try {
    parseScene("solver: {anderson: {windows: 3}}\n" + std::string(kValid), "blocks");
    ADD_FAILURE() << "an unknown field of a block accepted";
  } catch (const SceneError& e) {
    EXPECT_STREQ(e.what(),
                 "blocks: field 'solver.anderson.windows': unknown field (known here: window)");
  }
  try {  // a solver without settings of its own has no block
    parseScene("solver: {newton: {window: 3}}\n" + std::string(kValid), "blocks");
    ADD_FAILURE() << "a block of newton accepted";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.field(), "solver.newton");
  }
}

TEST(SceneOverrides, AResolutionKeepsPinsWhereTheyAreOnTheSheet) {
  SceneConfig scene = parseScene(std::string(kValid) +
                                     "pins: [{row: 3, col: 4}, {vertex: 4}, {edge: top}]\n"
                                     "self_collision: {thickness: 0.2}\n",
                                 "resized");
  ASSERT_EQ(scene.grid.rows, 4);
  ASSERT_EQ(scene.grid.cols, 5);
  SceneOverrides overrides;
  overrides.resolution = 7;
  const SceneConfig resized = applyOverrides(scene, overrides);
  EXPECT_EQ(resized.grid.rows, 7);
  EXPECT_EQ(resized.grid.cols, 7);
  EXPECT_EQ(resized.pins[0].row, 6);  // the far corner stays the far corner
  EXPECT_EQ(resized.pins[0].col, 6);
  EXPECT_EQ(resized.pins[1].vertex, 6);  // row 0, last column
  EXPECT_EQ(resized.pins[2].edge, "top");
  EXPECT_EQ(resized.options.self_contact.thickness, 0.0);  // automatic at the new spacing
  EXPECT_NO_THROW(makeSimulation(resized));

  SceneConfig mesh = scene;
  mesh.cloth_kind = SceneConfig::ClothKind::kMesh;
  EXPECT_THROW(applyOverrides(mesh, overrides), SceneError);
}

}  // namespace
}  // namespace cloth_sim
