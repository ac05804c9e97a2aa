/// @file scene_overrides.h
/// What a caller replaces in a scene before building it: the node's ~solver / ~iterations /
/// ~substeps / ~error_tolerance / ~self_collision / ~threads, the runner's --solver,
/// --iterations, --substeps, --tolerance, --error-tolerance, --linear-solver, --dt,
/// --warm-start, --integrator, --self-collision, --resolution and --threads, the benchmark's
/// configurations. Each caller checks its values against settings_table.h, naming them as it
/// calls them (Setting::refusal); Simulation checks the result when it is built.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "cloth_sim/core/io/scene_reader.h"

namespace cloth_sim {

/// Scene values to replace; an empty field keeps the scene's.
struct SceneOverrides {
  std::optional<std::string> solver;            ///< a name from solverNames()
  std::optional<int> iterations;                ///< SolverSettings::max_iterations
  std::optional<int> substeps;                  ///< SolverSettings::substeps
  std::optional<double> tolerance;              ///< SolverSettings::tolerance
  std::optional<double> error_tolerance;        ///< m, SolverSettings::error_tolerance
  std::optional<LinearSolver> linear_solver;    ///< SolverSettings::linear_solver
  std::optional<double> time_step;              ///< s
  std::optional<bool> warm_start;               ///< SolverSettings::warm_start
  std::optional<Integrator> integrator;         ///< SolverSettings::integrator
  std::optional<int> threads;                   ///< SolverSettings::threads
  /// Per-solver settings (SolverSettings::params), each replacing the scene's value.
  std::vector<std::pair<const SolverParam*, double>> params;
  /// SelfContactSettings::enabled (on with the scene's thickness and friction, or defaults).
  std::optional<bool> self_collision;
  /// A grid cloth of this many particles a side (rows = cols): a pin on a vertex or a row and
  /// column moves to the same place on the sheet (corners stay corners; edge and region
  /// selectors hold at any resolution); in self_collision.mode particles the thickness becomes
  /// automatic (the scene's was for its own spacing), in mode triangles it stays (the cloth's
  /// own). Refused for a mesh cloth.
  std::optional<int> resolution;
};

/// @p scene with the non-empty fields of @p overrides in place of its own. Throws SceneError
/// (field "cloth") for a resolution on a mesh cloth.
SceneConfig applyOverrides(SceneConfig scene, const SceneOverrides& overrides);

}  // namespace cloth_sim
