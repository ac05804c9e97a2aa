#include "cloth_sim/core/io/scene_overrides.h"

namespace cloth_sim {

SceneConfig applyOverrides(SceneConfig scene, const SceneOverrides& overrides) {
  SolverSettings& settings = scene.options.settings;
  if (overrides.solver) scene.options.solver = *overrides.solver;
  if (overrides.iterations) settings.max_iterations = *overrides.iterations;
  if (overrides.substeps) settings.substeps = *overrides.substeps;
  if (overrides.tolerance) settings.tolerance = *overrides.tolerance;
  if (overrides.linear_solver) settings.linear_solver = *overrides.linear_solver;
  if (overrides.warm_start) settings.warm_start = *overrides.warm_start;
  if (overrides.integrator) settings.integrator = *overrides.integrator;
  if (overrides.time_step) scene.time_step = *overrides.time_step;
  if (overrides.self_collision) scene.options.self_contact.enabled = *overrides.self_collision;
  return scene;
}

}  // namespace cloth_sim
