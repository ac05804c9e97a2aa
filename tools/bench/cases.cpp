#include "cases.h"

#include <cmath>

namespace cloth_sim::bench {

BenchCase makeCase(const std::string& scenes_dir, const std::string& scene, int grid) {
  BenchCase c;
  c.scene = scene;
  c.grid = grid;
  c.name = scene + "-" + std::to_string(grid);
  c.config = loadSceneFile(scenes_dir + "/" + scene + ".yaml");
  c.config.options.settings.substeps = 1;  // one implicit step per frame: the per-step view
  const int old_rows = c.config.grid.rows, old_cols = c.config.grid.cols;
  c.config.grid.rows = grid;
  c.config.grid.cols = grid;
  // A pin on one grid vertex moves to the same place on the sheet at the new resolution (corners
  // stay corners); edge and region selectors resolve at any resolution as they are.
  auto scale = [grid](int index, int old_count) {
    return static_cast<int>(std::lround(static_cast<double>(index) * (grid - 1) / (old_count - 1)));
  };
  for (PinSelector& pin : c.config.pins) {
    if (pin.kind == PinSelector::Kind::kVertex) {
      pin.vertex = gridVertex(scale(pin.vertex / old_cols, old_rows),
                              scale(pin.vertex % old_cols, old_cols), grid);
    } else if (pin.kind == PinSelector::Kind::kCell) {
      pin.row = scale(pin.row, old_rows);
      pin.col = scale(pin.col, old_cols);
    }
  }
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
  config.options.solver = solver;
  config.options.settings.max_iterations = iterations;
  config.options.settings.linear_solver = linear;
  config.options.settings.warm_start = warm_start;
  return config;
}

}  // namespace cloth_sim::bench
