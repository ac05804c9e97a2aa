#include "cases.h"

#include <utility>

namespace cloth_sim::bench {

SceneConfig fixedConfiguration(SceneConfig config) {
  SolverFieldsGiven& given = config.given;
  if (!given.error_tolerance) config.options.settings.error_tolerance = 0.0;
  given = SolverFieldsGiven{true, true, true, true};
  return config;
}

BenchCase makeCase(const std::string& scenes_dir, const std::string& scene, int grid) {
  BenchCase c;
  c.scene = scene;
  c.grid = grid;
  c.name = scene + "-" + std::to_string(grid);
  SceneOverrides resized;
  resized.resolution = grid;  // pins stay where they are on the sheet
  resized.substeps = 1;       // one implicit step per frame: the per-step view
  c.config =
      applyOverrides(fixedConfiguration(loadSceneFile(scenes_dir + "/" + scene + ".yaml")), resized);
  return c;
}

BenchCase makePaperCase(const std::string& scenes_dir) {
  BenchCase c = makeCase(scenes_dir, "hanging", 81);
  c.name = "paper-81";
  c.paper = true;
  c.config.grid.shear_pattern = ShearPattern::kTriangle;
  c.config.grid.material.has_bending = true;
  c.config.time_step = 1.0 / 30.0;
  return c;
}

SceneConfig withSolver(SceneConfig config, const std::string& solver, int iterations,
                       LinearSolver linear, bool warm_start) {
  SceneOverrides overrides;
  overrides.solver = solver;
  overrides.iterations = iterations;
  overrides.linear_solver = linear;
  overrides.warm_start = warm_start;
  return applyOverrides(std::move(config), overrides);
}

}  // namespace cloth_sim::bench
