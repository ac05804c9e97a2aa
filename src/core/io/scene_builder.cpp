#include "cloth_sim/core/io/scene_builder.h"

#include <set>

#include "cloth_sim/core/model/grid_builder.h"

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

}  // namespace

BuiltObject buildCloth(const SceneConfig& scene) {
  BuiltObject object = scene.cloth_kind == SceneConfig::ClothKind::kGrid ? buildGrid(scene.grid)
                                                                         : buildMeshObject(scene.mesh);
  object.model.time_step = scene.time_step;
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

Simulation makeSimulation(const SceneConfig& scene) {
  BuiltObject object = buildCloth(scene);
  PinSet pins;
  for (const PinSpec& p : resolvePins(scene, object.rest_positions)) {
    pins.add(p.vertex, p.target.value_or(Vec3(object.rest_positions.col(p.vertex))), p.stiffness,
             object.model.particleCount());
  }
  Colliders colliders;
  for (const SphereCollider& s : scene.spheres) colliders.addSphere(s);
  for (const MeshColliderSpec& m : scene.meshes) colliders.addMesh(m.obstacle);
  colliders.setGround(scene.ground);
  return Simulation(std::move(object.model), object.rest_positions, std::move(pins),
                    std::move(colliders), scene.options);
}

}  // namespace cloth_sim
