/// @file scene_overrides.h
/// What a caller replaces in a scene before building it: the node's ~solver / ~iterations /
/// ~substeps, the runner's --solver, --iterations, --substeps, --tolerance, --linear-solver, --dt,
/// --warm-start, --integrator. Each caller
/// checks its values against settings_table.h in its own message format; Simulation checks the
/// result again when it is built.
#pragma once

#include <optional>
#include <string>

#include "cloth_sim/core/io/scene_reader.h"

namespace cloth_sim {

/// Scene values to replace; an empty field keeps the scene's.
struct SceneOverrides {
  std::optional<std::string> solver;            ///< a name from solverNames()
  std::optional<int> iterations;                ///< SolverSettings::max_iterations
  std::optional<int> substeps;                  ///< SolverSettings::substeps
  std::optional<double> tolerance;              ///< SolverSettings::tolerance
  std::optional<LinearSolver> linear_solver;    ///< SolverSettings::linear_solver
  std::optional<double> time_step;              ///< s
  std::optional<bool> warm_start;               ///< SolverSettings::warm_start
  std::optional<Integrator> integrator;         ///< SolverSettings::integrator
  /// SelfContactSettings::enabled (on with the scene's thickness and friction, or defaults).
  std::optional<bool> self_collision;
};

/// @p scene with the non-empty fields of @p overrides in place of its own.
SceneConfig applyOverrides(SceneConfig scene, const SceneOverrides& overrides);

}  // namespace cloth_sim
