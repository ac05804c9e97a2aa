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

/// Builds the simulation the scene describes (the cloth once). Throws SceneError.
Simulation makeSimulation(const SceneConfig& scene);

}  // namespace cloth_sim
