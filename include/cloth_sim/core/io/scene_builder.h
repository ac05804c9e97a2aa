/// @file scene_builder.h
/// Scene data (scene_reader.h) made into a simulation: the cloth is built once and the pin
/// selectors are resolved against its rest positions. Errors still name the scene field.
#pragma once

#include <optional>
#include <vector>

#include "cloth_sim/core/io/scene_reader.h"

namespace cloth_sim {

/// A pin resolved to a vertex index.
struct PinSpec {
  int vertex = -1;
  std::optional<Vec3> target;  ///< m; empty = where the vertex rests
  double stiffness = 0.0;      ///< N/m; 0 = hard pin
};

/// The cloth object (model and rest positions) the scene describes, grid or mesh, with its
/// gravity and damping set (the time step goes to SimulationOptions::frame_time).
BuiltObject buildCloth(const SceneConfig& scene);

/// The pins of @p scene, in scene order, on the cloth whose rest positions are @p rest (from
/// buildCloth). An edge or region pin holds each of its vertices once, skipping vertices an
/// earlier entry already holds. Throws SceneError naming the entry ("pins[2].region") for an
/// index out of range, an empty region or a vertex pinned twice by single-vertex entries.
std::vector<PinSpec> resolvePins(const SceneConfig& scene, const Points& rest);

/// The solver settings of @p scene with the fields it did not give (SceneConfig::given) chosen
/// for its solver, @p size (m) the cloth's size (diagonal of its bounding box at rest):
///  - a scene that gives none of substeps, iterations and error_tolerance, with a solver that
///    iterates to a tolerance (its registry entry's capabilities), gets error control: a
///    tolerance of kDefaultRelativeErrorTolerance x size, substeps chosen by the error estimate
///    (0), iterations capped at kDefaultIterationCap, BDF2 unless it names an integrator;
///  - a scene that gives error_tolerance > 0 or substeps 0 gets the same for the fields it
///    leaves out;
///  - otherwise (substeps or iterations given, error_tolerance 0, or a solver without a
///    convergence test: explicit, xpbd) the configuration is fixed: implicit Euler's 8 substeps
///    of 2 iterations (defaultSceneOptions()) where the scene does not say otherwise.
SolverSettings resolveSolverDefaults(const SceneConfig& scene, double size);

/// Builds the simulation the scene describes (the cloth once). Throws SceneError.
Simulation makeSimulation(const SceneConfig& scene);

}  // namespace cloth_sim
