#include "cloth_sim/core/io/scene_overrides.h"

#include <cmath>

#include "cloth_sim/core/model/grid_builder.h"

namespace cloth_sim {
namespace {

/// @p scene's grid at @p n x @p n particles, its pins moved to the same place on the sheet.
void resize(SceneConfig& scene, int n) {
  if (scene.cloth_kind != SceneConfig::ClothKind::kGrid) {
    throw SceneError(scene.source, "cloth", "a resolution needs a grid cloth; this one is a mesh");
  }
  const int old_rows = scene.grid.rows, old_cols = scene.grid.cols;
  scene.grid.rows = scene.grid.cols = n;
  // Index i of a side of @p old_count particles, at the same fraction of the side at n; an
  // index off the side stays as it is, for the builder to refuse.
  auto scale = [n](int index, int old_count) {
    if (index < 0 || index >= old_count) return index;
    return static_cast<int>(std::lround(static_cast<double>(index) * (n - 1) / (old_count - 1)));
  };
  for (PinSelector& pin : scene.pins) {
    if (pin.kind == PinSelector::Kind::kVertex && pin.vertex >= 0 &&
        pin.vertex < old_rows * old_cols) {
      pin.vertex = gridVertex(scale(pin.vertex / old_cols, old_rows),
                              scale(pin.vertex % old_cols, old_cols), n);
    } else if (pin.kind == PinSelector::Kind::kCell) {
      pin.row = scale(pin.row, old_rows);
      pin.col = scale(pin.col, old_cols);
    }
  }
  // Mode particles' thickness is about the spacing: automatic at the new one. Mode triangles'
  // is the cloth's own, whatever its mesh.
  if (scene.options.self_contact.mode == SelfContactMode::kParticles) {
    scene.options.self_contact.thickness = 0.0;
  }
}

}  // namespace

SceneConfig applyOverrides(SceneConfig scene, const SceneOverrides& overrides) {
  SolverSettings& settings = scene.options.settings;
  if (overrides.solver) scene.options.solver = *overrides.solver;
  if (overrides.iterations) {
    settings.max_iterations = *overrides.iterations;
    scene.given.iterations = true;
  }
  if (overrides.substeps) {
    settings.substeps = *overrides.substeps;
    scene.given.substeps = true;
  }
  if (overrides.tolerance) settings.tolerance = *overrides.tolerance;
  if (overrides.error_tolerance) {
    settings.error_tolerance = *overrides.error_tolerance;
    scene.given.error_tolerance = true;
  }
  if (overrides.linear_solver) settings.linear_solver = *overrides.linear_solver;
  if (overrides.warm_start) settings.warm_start = *overrides.warm_start;
  if (overrides.integrator) {
    settings.integrator = *overrides.integrator;
    scene.given.integrator = true;
  }
  if (overrides.threads) settings.threads = *overrides.threads;
  for (const auto& [param, value] : overrides.params) settings.params.set(*param, value);
  if (overrides.time_step) scene.time_step = *overrides.time_step;
  if (overrides.self_collision) scene.options.self_contact.enabled = *overrides.self_collision;
  if (overrides.resolution) resize(scene, *overrides.resolution);
  return scene;
}

}  // namespace cloth_sim
