#include "cloth_sim/core/io/scene_builder.h"

#include <algorithm>
#include <set>
#include <sstream>

#include "cloth_sim/core/io/scene_limits.h"
#include "cloth_sim/core/model/grid_builder.h"
#include "cloth_sim/core/settings/range.h"
#include "cloth_sim/core/solvers/registry.h"

namespace cloth_sim {
namespace {

/// Fails with the scene's message format for @p pin's field (plus @p sub, e.g. ".row").
[[noreturn]] void fail(const SceneConfig& scene, const PinSelector& pin, const std::string& sub,
                       const std::string& problem) {
  throw SceneError(scene.source, (pin.field.empty() ? "pins" : pin.field) + sub, problem);
}

/// @p index, checked to lie in [0, count).
int checkedIndex(const SceneConfig& scene, const PinSelector& pin, const std::string& sub,
                 int index, int count) {
  if (index < 0 || index >= count) {
    fail(scene, pin, sub, "value " + std::to_string(index) + " must be an integer in [0, " +
                              std::to_string(count - 1) + "]");
  }
  return index;
}

/// Vertices of a grid edge: "top" (row 0), "bottom", "left" (col 0), "right" or "all".
std::vector<int> edgeVertices(const GridSpec& g, const std::string& edge) {
  std::vector<int> out;
  const bool all = edge == "all";
  for (int r = 0; r < g.rows; ++r) {
    for (int c = 0; c < g.cols; ++c) {
      if ((all || edge == "top") && r == 0) out.push_back(gridVertex(r, c, g.cols));
      else if ((all || edge == "bottom") && r == g.rows - 1) out.push_back(gridVertex(r, c, g.cols));
      else if ((all || edge == "left") && c == 0) out.push_back(gridVertex(r, c, g.cols));
      else if ((all || edge == "right") && c == g.cols - 1) out.push_back(gridVertex(r, c, g.cols));
    }
  }
  return out;
}

/// Vertices whose rest position lies in @p box.
std::vector<int> regionVertices(const Eigen::AlignedBox3d& box, const Points& rest) {
  std::vector<int> out;
  for (Eigen::Index v = 0; v < rest.cols(); ++v) {
    if (box.contains(Vec3(rest.col(v)))) out.push_back(static_cast<int>(v));
  }
  return out;
}

/// A length this small relative to the coordinates around it keeps fewer than 6 significant
/// digits in double precision (2.2e-16 / 1e-9): the springs' rest lengths, their strains and the
/// contacts would be computed from rounding noise (e.g. a 1 m cloth placed at x = 1e300 has every
/// rest length 0).
constexpr double kLengthResolution = 1e-9;

/// The cloth's shortest spring or edge must be resolvable where the cloth is: at least
/// kLengthResolution times its farthest coordinate.
void checkPrecision(const SceneConfig& scene, const BuiltObject& object) {
  const auto& rest = object.model.springs.rest_length;
  const Points& x = object.rest_positions;
  double shortest = rest.empty() ? Range::kInfinity : *std::min_element(rest.begin(), rest.end());
  const Eigen::Matrix3Xi& triangles = object.model.triangles;  // the edges a spring may skip
  for (Eigen::Index t = 0; t < triangles.cols(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const double edge = (x.col(triangles(k, t)) - x.col(triangles((k + 1) % 3, t))).norm();
      shortest = std::min(shortest, edge);
    }
  }
  const double farthest = object.rest_positions.cwiseAbs().maxCoeff();
  if (shortest >= kLengthResolution * farthest) return;
  const bool grid = scene.cloth_kind == SceneConfig::ClothKind::kGrid;
  std::ostringstream s;
  s << "the shortest spring or triangle edge, " << shortest << " m, is less than " << kLengthResolution
    << " times the cloth's farthest coordinate, " << farthest
    << " m: rest lengths would lose their precision (move the cloth nearer the origin or make "
    << (grid ? "it larger or its grid coarser)" : "it larger)");
  throw SceneError(scene.source, grid ? "cloth.grid.position" : "cloth.mesh.position", s.str());
}

/// What the scene puts around its cloth must be something the simulation can follow
/// (scene_limits.h): pin targets and spheres within reach, spheres no larger than the cloth, no
/// far heavier, no faster than their radius per implicit step; the ground below the cloth.
void checkLimits(const SceneConfig& scene, const Simulation& sim) {
  const SceneLimits limits = SceneLimits::of(sim);
  for (const PinSelector& pin : scene.pins) {
    if (!pin.target) continue;
    try {
      limits.checkPoint("value", *pin.target);
    } catch (const std::invalid_argument& e) {
      fail(scene, pin, ".target", e.what());
    }
  }
  const double lowest = sim.initialPositions().row(2).minCoeff();
  if (scene.ground.enabled && scene.ground.height > lowest) {
    std::ostringstream s;
    s << "value " << scene.ground.height << " m must be at most the cloth's lowest initial "
      << "height, " << lowest << " m (a ground above the cloth would throw it up past its pins)";
    throw SceneError(scene.source, "colliders.ground.height", s.str());
  }
  for (std::size_t k = 0; k < scene.spheres.size(); ++k) {
    try {
      limits.checkSphere("", scene.spheres[k], sim.substepTime());
    } catch (const std::invalid_argument& e) {
      throw SceneError(scene.source, "colliders.spheres[" + std::to_string(k) + "]", e.what());
    }
  }
}

}  // namespace

BuiltObject buildCloth(const SceneConfig& scene) {
  BuiltObject object = scene.cloth_kind == SceneConfig::ClothKind::kGrid ? buildGrid(scene.grid)
                                                                         : buildMeshObject(scene.mesh);
  object.model.gravity = scene.gravity;
  object.model.damping = scene.damping;
  return object;
}

std::vector<PinSpec> resolvePins(const SceneConfig& scene, const Points& rest) {
  const GridSpec& g = scene.grid;
  const int count = static_cast<int>(rest.cols());
  std::vector<PinSpec> out;
  std::set<int> used;
  for (const PinSelector& pin : scene.pins) {
    using Kind = PinSelector::Kind;
    if (pin.kind == Kind::kEdge || pin.kind == Kind::kRegion) {
      const std::vector<int> vertices =
          pin.kind == Kind::kEdge ? edgeVertices(g, pin.edge) : regionVertices(pin.region, rest);
      if (pin.kind == Kind::kRegion && vertices.empty()) {
        fail(scene, pin, ".region", "contains no vertex of the cloth");
      }
      // Vertices already pinned by an earlier entry (shared corners) are pinned once.
      for (int v : vertices) {
        if (used.insert(v).second) out.push_back(PinSpec{v, std::nullopt, pin.stiffness});
      }
      continue;
    }
    const int vertex =
        pin.kind == Kind::kVertex
            ? checkedIndex(scene, pin, ".vertex", pin.vertex, count)
            : gridVertex(checkedIndex(scene, pin, ".row", pin.row, g.rows),
                         checkedIndex(scene, pin, ".col", pin.col, g.cols), g.cols);
    if (!used.insert(vertex).second) {
      fail(scene, pin, "", "vertex " + std::to_string(vertex) + " is already pinned");
    }
    out.push_back(PinSpec{vertex, pin.target, pin.stiffness});
  }
  return out;
}

SolverSettings resolveSolverDefaults(const SceneConfig& scene, double size) {
  SolverSettings s = scene.options.settings;
  const SolverFieldsGiven& given = scene.given;
  const SolverCapabilities& can = solverEntry(scene.options.solver).capabilities;
  if (!can.tolerance) return s;
  // A scene that fixes substeps or iterations keeps a fixed configuration unless it asks for
  // error control itself (an error tolerance, or substeps 0); one that says neither gets it.
  const bool asks = s.substeps == 0 || (!given.substeps && !given.iterations);
  if (!given.error_tolerance && asks) {
    s.error_tolerance = kDefaultRelativeErrorTolerance * size;
  }
  if (s.error_tolerance <= 0.0) return s;  // fixed: as defaultSceneOptions() and the scene say
  if (!given.integrator && can.supports(Integrator::kBdf2)) s.integrator = Integrator::kBdf2;
  if (!given.substeps) s.substeps = 0;
  if (!given.iterations) s.max_iterations = kDefaultIterationCap;
  return s;
}

Simulation makeSimulation(const SceneConfig& scene) {
  BuiltObject object = buildCloth(scene);
  checkPrecision(scene, object);
  PinSet pins;
  for (const PinSpec& p : resolvePins(scene, object.rest_positions)) {
    pins.add(p.vertex, p.target.value_or(Vec3(object.rest_positions.col(p.vertex))), p.stiffness,
             object.model.particleCount());
  }
  Colliders colliders;
  for (const SphereCollider& s : scene.spheres) colliders.addSphere(s);
  for (const MeshColliderSpec& m : scene.meshes) colliders.addMesh(m.obstacle);
  for (const BodyCollider& b : scene.bodies) colliders.mutableBodies().add(b);
  colliders.setGround(scene.ground);
  SimulationOptions options = scene.options;
  const Points& rest = object.rest_positions;
  options.settings =
      resolveSolverDefaults(scene, (rest.rowwise().maxCoeff() - rest.rowwise().minCoeff()).norm());
  options.frame_time = scene.time_step;
  Simulation sim(std::move(object.model), object.rest_positions, std::move(pins),
                 std::move(colliders), std::move(options));
  checkLimits(scene, sim);
  return sim;
}

}  // namespace cloth_sim
