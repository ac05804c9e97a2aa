/// @file scene.h
/// Scene files: YAML (yaml-cpp) loaded into validated, plain parameters (cartographer style:
/// parsed into a struct and checked in one place, with a message naming field, value and rule).
#pragma once

#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "cloth_sim/core/colliders.h"
#include "cloth_sim/core/grid_builder.h"
#include "cloth_sim/core/simulation.h"

namespace cloth_sim {

/// A scene file that cannot be used. what() reads
/// "<source>: field '<path>': <value> <rule>" (or a YAML syntax error with its line).
class SceneError : public std::runtime_error {
 public:
  SceneError(const std::string& source, const std::string& field, const std::string& problem);
  /// Dotted path of the offending field, e.g. "cloth.grid.rows" or "pins[2].row".
  const std::string& field() const { return field_; }

 private:
  std::string field_;
};

/// A pin as a scene declares it, resolved to a vertex index.
struct PinSpec {
  int vertex = -1;
  std::optional<Vec3> target;  ///< m; empty = where the vertex rests
  double stiffness = 0.0;      ///< N/m; 0 = hard pin
};

/// Everything a scene file declares, validated.
struct SceneConfig {
  std::string name;         ///< scene name (file stem unless given)
  std::string description;  ///< free text
  std::string source;       ///< file path or the name passed to parseScene
  GridSpec grid;
  double time_step = 1.0 / 60.0;  ///< s
  Vec3 gravity = standardGravity();
  double damping = 0.0;     ///< 1/s, Model::damping
  SimulationOptions options;
  std::vector<PinSpec> pins;
  std::vector<SphereCollider> spheres;
  GroundPlane ground;       ///< disabled unless the scene has colliders.ground
};

/// Parses scene YAML text; @p source names it in error messages. Throws SceneError.
SceneConfig parseScene(const std::string& yaml_text, const std::string& source);
/// Reads and parses a scene file. Throws SceneError (also when it cannot be read).
SceneConfig loadSceneFile(const std::string& path);
/// Builds the simulation the scene describes.
Simulation makeSimulation(const SceneConfig& scene);

}  // namespace cloth_sim
