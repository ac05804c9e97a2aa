/// @file scene_reader.h
/// Scene files (docs/scene_format.md): YAML (yaml-cpp) turned into plain, validated data. The
/// reader builds nothing: pins stay selectors (vertex, row/col, edge, region) until
/// scene_builder.h resolves them against the cloth it builds. Each number is checked against its
/// entry in settings/settings_table.h (a solver's block against its registry entry's settings),
/// the message naming field, value and rule (SceneError, Setting::refusal). The typed reading
/// of the YAML nodes is scene_fields.h.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "cloth_sim/core/collision/colliders.h"
#include "cloth_sim/core/io/scene_error.h"
#include "cloth_sim/core/model/grid_builder.h"
#include "cloth_sim/core/model/mesh_builder.h"
#include "cloth_sim/core/simulation/simulation.h"

namespace cloth_sim {

/// Which vertices one entry of 'pins' holds, as the scene says it (resolved by resolvePins).
struct PinSelector {
  enum class Kind {
    kVertex,  ///< one vertex by index
    kCell,    ///< one grid vertex by row and column
    kEdge,    ///< every vertex on a grid edge
    kRegion,  ///< every vertex whose rest position is in a box
  };
  Kind kind = Kind::kVertex;
  int vertex = -1;             ///< kVertex
  int row = -1, col = -1;      ///< kCell
  std::string edge;            ///< kEdge: "top" (row 0), "bottom", "left" (col 0), "right", "all"
  Eigen::AlignedBox3d region;  ///< kRegion: m, world frame, not empty
  std::optional<Vec3> target;  ///< m; single-vertex kinds only; empty = where the vertex rests
  double stiffness = 0.0;      ///< N/m; 0 = hard pin
  std::string field;           ///< the entry in the scene, "pins[2]", for error messages

  /// A hard pin on @p vertex where it rests (what a program, not a file, usually wants).
  static PinSelector atVertex(int vertex);
};

/// A static mesh obstacle as a scene declares it, loaded and placed in the world.
struct MeshColliderSpec {
  std::string file;                              ///< resolved path of the OBJ
  std::shared_ptr<const MeshObstacle> obstacle;  ///< world frame, thickness and friction set
};

/// The solver fields a scene (or a caller's SceneOverrides) set. The others take the defaults
/// of the solver in use when the simulation is built (resolveSolverDefaults).
struct SolverFieldsGiven {
  bool integrator = false;       ///< solver.integrator
  bool iterations = false;       ///< solver.iterations
  bool substeps = false;         ///< solver.substeps
  bool error_tolerance = false;  ///< solver.error_tolerance
};

/// Default error tolerance of a scene, as a share of the cloth's size (the diagonal of its
/// bounding box at rest): 1e-5 x the diagonal per frame. Chosen from the accuracy benchmark
/// (docs/benchmark.md, "Error control"): on the untuned scenes it keeps the RMS error at 1 s
/// against the true motion near 1 % of the size.
inline constexpr double kDefaultRelativeErrorTolerance = 1e-5;
/// Default cap on the iterations of one implicit step under error control: the tolerance
/// stops them, the cap only bounds a step that cannot reach it.
inline constexpr int kDefaultIterationCap = 100;

/// What a scene gets before resolveSolverDefaults: local_global; the fields it does not give
/// are then chosen for the solver in use.
inline SimulationOptions defaultSceneOptions() {
  SimulationOptions options;
  options.settings.substeps = 8;
  options.settings.max_iterations = 2;
  return options;
}

/// Everything a scene file declares, validated.
struct SceneConfig {
  std::string name;         ///< scene name (file stem unless given)
  std::string description;  ///< free text
  std::string source;       ///< file path or the name passed to parseScene
  /// The cloth is a grid (cloth.grid) or any triangle mesh from an OBJ file (cloth.mesh).
  enum class ClothKind { kGrid, kMesh } cloth_kind = ClothKind::kGrid;
  GridSpec grid;            ///< when cloth_kind == kGrid (geometry and material)
  MeshSpec mesh;            ///< when cloth_kind == kMesh (world coordinates and material)
  double time_step = 1.0 / 60.0;  ///< s
  Vec3 gravity = standardGravity();
  double damping = 0.0;     ///< 1/s, Model::damping
  SimulationOptions options = defaultSceneOptions();
  SolverFieldsGiven given;  ///< which of options.settings' solver fields the scene set
  std::vector<PinSelector> pins;  ///< in scene order
  std::vector<SphereCollider> spheres;
  std::vector<MeshColliderSpec> meshes;
  /// colliders.bodies[]: still ones placed, ones on a frame named (BodyCollider::name) with
  /// their origin in it (scene_bodies.h).
  std::vector<BodyCollider> bodies;
  GroundPlane ground;       ///< disabled unless the scene has colliders.ground
};

/// Parses scene YAML text; @p source names it in error messages, and relative mesh file paths
/// are resolved against its directory. Throws SceneError.
SceneConfig parseScene(const std::string& yaml_text, const std::string& source);
/// Reads and parses a scene file. Throws SceneError (also when it cannot be read).
SceneConfig loadSceneFile(const std::string& path);

}  // namespace cloth_sim
