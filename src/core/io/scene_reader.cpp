#include "cloth_sim/core/io/scene_reader.h"

#include <fstream>
#include <set>
#include <sstream>

#include "cloth_sim/core/io/scene_bodies.h"
#include "cloth_sim/core/io/scene_fields.h"
#include "cloth_sim/core/solvers/registry.h"

namespace cloth_sim {

PinSelector PinSelector::atVertex(int vertex) {
  PinSelector pin;
  pin.vertex = vertex;
  return pin;
}

namespace {

/// solver: {name, iterations, substeps, tolerance, integrator, error_tolerance, threads} and, for
/// every solver of the registry that has settings of its own, its block solver.<name>:
/// {<field>: value, ...}.
void readSolver(const SceneFields& r, const YAML::Node& node, SimulationOptions& options,
                SolverFieldsGiven& given) {
  const std::string path = "solver";
  std::set<std::string> keys = {"name",      "iterations", "substeps",
                                 "tolerance", "integrator", "error_tolerance", "threads"};
  for (const SolverEntry& entry : solverRegistry()) {
    if (!entry.params.empty()) keys.insert(entry.name);
  }
  r.map(node, path, keys);
  if (node["name"]) {
    options.solver = r.word(node["name"], path + ".name");
    try {
      solverEntry(options.solver);  // throws the message listing the names
    } catch (const std::invalid_argument& e) {
      r.fail(path + ".name", e.what());
    }
  }
  SolverSettings& s = options.settings;
  if (node["integrator"]) {
    const std::string name = r.word(node["integrator"], settings::kIntegrator.name);
    given.integrator = true;
    try {  // the message lists the names
      s.integrator = integratorFromName(name);
    } catch (const std::invalid_argument& e) {
      r.fail(settings::kIntegrator.name, e.what());
    }
  }
  if (node["iterations"]) {
    given.iterations = true;
    s.max_iterations =
        r.integer(node["iterations"], settings::kIterations.name, settings::kIterations);
  }
  if (node["substeps"]) {
    given.substeps = true;
    s.substeps = r.integer(node["substeps"], settings::kSubsteps.name, settings::kSubsteps);
  }
  if (node["error_tolerance"]) {
    given.error_tolerance = true;
    s.error_tolerance = r.number(node["error_tolerance"], settings::kErrorTolerance.name,
                                 settings::kErrorTolerance);
  }
  if (node["tolerance"]) {
    s.tolerance = r.number(node["tolerance"], settings::kTolerance.name, settings::kTolerance);
  }
  if (node["threads"]) {
    s.threads = r.integer(node["threads"], settings::kThreads.name, settings::kThreads);
  }
  for (const SolverEntry& entry : solverRegistry()) {
    const YAML::Node block = node[entry.name];
    if (!block) continue;
    const std::string block_path = SceneFields::join(path, entry.name);
    std::set<std::string> fields;
    for (const SolverParam* param : entry.params) fields.insert(param->field());
    r.map(block, block_path, fields);
    for (const SolverParam* param : entry.params) {
      const YAML::Node value = block[param->field()];
      if (!value) continue;
      s.params.set(*param, param->integer ? r.integer(value, param->name, *param)
                                          : r.number(value, param->name, *param));
    }
  }
}

/// position [m] and orientation_rpy [rad] (fixed-axis roll about X, then pitch about Y, then yaw
/// about Z, REP-103), both optional.
Eigen::Isometry3d readPose(const SceneFields& r, const YAML::Node& node, const std::string& path) {
  Vec3 position = Vec3::Zero(), rpy = Vec3::Zero();
  if (node["position"]) position = r.point(node["position"], path + ".position");
  if (node["orientation_rpy"]) rpy = r.vec3(node["orientation_rpy"], path + ".orientation_rpy");
  return Eigen::Translation3d(position) * Eigen::AngleAxisd(rpy.z(), Vec3::UnitZ()) *
         Eigen::AngleAxisd(rpy.y(), Vec3::UnitY()) * Eigen::AngleAxisd(rpy.x(), Vec3::UnitX());
}

/// An OBJ file placed in the world: file (relative to the scene), position, orientation_rpy,
/// scale. Errors from the file are reported on the 'file' field.
TriangleMesh readPlacedMesh(const SceneFields& r, const YAML::Node& node, const std::string& path,
                            std::string& resolved) {
  if (!node["file"]) r.fail(path + ".file", "is required (an OBJ file)");
  resolved = r.resolve(r.text(node["file"], path + ".file"));
  double scale = 1.0;
  if (node["scale"]) scale = r.number(node["scale"], path + ".scale", settings::kMeshScale);
  TriangleMesh mesh;
  try {
    mesh = loadObj(resolved).transformed(readPose(r, node, path), scale);
  } catch (const std::invalid_argument& e) {
    r.fail(path + ".file", e.what());
  }
  // Placed, every vertex must still be a point of the scene (settings::kCoordinate).
  const double farthest = mesh.vertices.size() > 0 ? mesh.vertices.cwiseAbs().maxCoeff() : 0.0;
  if (!settings::kCoordinate.allows(farthest)) {
    r.fail(path + ".scale",
           "value " + formatNumber(scale) + " (with the position) puts a vertex of " + resolved +
               " out of the scene: " + settings::kCoordinate.refusal(farthest, "its coordinate"));
  }
  return mesh;
}

void readClothMesh(const SceneFields& r, const YAML::Node& node, SceneConfig& scene) {
  const std::string path = "cloth.mesh";
  r.map(node, path, {"file", "position", "orientation_rpy", "scale"});
  std::string resolved;
  scene.mesh.mesh = readPlacedMesh(r, node, path, resolved);
  scene.mesh.source = resolved;
  try {
    validateClothSurface(scene.mesh.mesh, resolved);
  } catch (const std::invalid_argument& e) {
    r.fail(path + ".file", e.what());
  }
  scene.cloth_kind = SceneConfig::ClothKind::kMesh;
}

void readGrid(const SceneFields& r, const YAML::Node& node, GridSpec& grid) {
  const std::string path = "cloth.grid";
  r.map(node, path, {"rows", "cols", "size", "position", "orientation_rpy"});
  if (!node["rows"]) r.fail(path + ".rows", "is required");
  if (!node["cols"]) r.fail(path + ".cols", "is required");
  if (!node["size"]) r.fail(path + ".size", "is required ([width, height] in m)");
  grid.rows = r.integer(node["rows"], path + ".rows", settings::kGridResolution);
  grid.cols = r.integer(node["cols"], path + ".cols", settings::kGridResolution);
  const YAML::Node size = node["size"];
  if (!size.IsSequence() || size.size() != 2) {
    r.fail(path + ".size", "value " + SceneFields::show(size) + " must be [width, height] in m");
  }
  grid.width = r.number(size[0], path + ".size[0]", settings::kGridSize);
  grid.height = r.number(size[1], path + ".size[1]", settings::kGridSize);
  grid.pose = readPose(r, node, path);
}

void readMaterial(const SceneFields& r, const YAML::Node& node, SceneConfig& scene) {
  const std::string path = "material";
  r.map(node, path, {"areal_density", "damping", "springs", "shear_pattern"});
  const bool mesh = scene.cloth_kind == SceneConfig::ClothKind::kMesh;
  Material& material = mesh ? scene.mesh.material : scene.grid.material;
  if (node["areal_density"]) {
    material.areal_density =
        r.number(node["areal_density"], path + ".areal_density", settings::kArealDensity);
  }
  if (node["damping"]) {
    scene.damping = r.number(node["damping"], path + ".damping", settings::kDamping);
  }
  if (!node["springs"]) r.fail(path + ".springs", "is required (stiffness per family, N/m)");
  const YAML::Node springs = node["springs"];
  const std::string sp = path + ".springs";
  r.map(springs, sp, {"structural", "shear", "bending"});
  auto family = [&](const char* key, const Setting& setting, bool& has, double& k) {
    has = static_cast<bool>(springs[key]);
    if (has) k = r.number(springs[key], sp + "." + key, setting);
  };
  family("structural", settings::kStructuralStiffness, material.has_structural,
         material.structural);
  family("shear", settings::kShearStiffness, material.has_shear, material.shear);
  family("bending", settings::kBendingStiffness, material.has_bending, material.bending);
  if (!material.has_structural && !material.has_shear && !material.has_bending) {
    r.fail(sp, "must declare at least one family (structural, shear, bending)");
  }
  if (node["shear_pattern"]) {
    const std::string p = r.word(node["shear_pattern"], path + ".shear_pattern");
    if (p == "both") scene.grid.shear_pattern = ShearPattern::kBoth;
    else if (p == "triangle") scene.grid.shear_pattern = ShearPattern::kTriangle;
    else r.fail(path + ".shear_pattern", "value '" + p + "' must be 'both' or 'triangle'");
  }
  if (mesh) {
    const std::string why = "a mesh cloth has springs on its edges (structural) and across them "
                            "(bending) only";
    if (material.has_shear) r.fail(sp + ".shear", why);
    if (node["shear_pattern"]) r.fail(path + ".shear_pattern", why);
  }
}

/// A box {min: [x,y,z], max: [x,y,z]} (m, world) with min <= max on every axis.
Eigen::AlignedBox3d readRegion(const SceneFields& r, const YAML::Node& node,
                               const std::string& path) {
  r.map(node, path, {"min", "max"});
  if (!node["min"] || !node["max"]) r.fail(path, "needs 'min' and 'max' corners [x, y, z] in m");
  const Eigen::AlignedBox3d box(r.point(node["min"], path + ".min"), r.point(node["max"], path + ".max"));
  if (box.isEmpty()) r.fail(path, "'min' must not exceed 'max' on any axis");
  return box;
}

/// Each entry's form; indices are checked against the cloth by resolvePins.
void readPins(const SceneFields& r, const YAML::Node& node, SceneConfig& scene) {
  if (!node.IsSequence()) r.fail("pins", "value " + SceneFields::show(node) + " must be a list");
  const bool grid = scene.cloth_kind == SceneConfig::ClothKind::kGrid;
  for (std::size_t k = 0; k < node.size(); ++k) {
    PinSelector pin;
    pin.field = "pins[" + std::to_string(k) + "]";
    const std::string& path = pin.field;
    const YAML::Node p = node[k];
    r.map(p, path, {"vertex", "row", "col", "edge", "region", "target", "stiffness"});
    const bool by_cell = p["row"] || p["col"];
    const int ways = (p["vertex"] ? 1 : 0) + (by_cell ? 1 : 0) + (p["edge"] ? 1 : 0) +
                     (p["region"] ? 1 : 0);
    if (ways != 1) {
      r.fail(path, "give exactly one of 'vertex', 'row' + 'col', 'edge' or 'region'");
    }
    if (!grid && (by_cell || p["edge"])) {
      r.fail(path, "'row', 'col' and 'edge' need a grid cloth; use 'vertex' or 'region'");
    }
    if (p["stiffness"]) {
      pin.stiffness = r.number(p["stiffness"], path + ".stiffness", settings::kPinStiffness);
    }
    if (p["edge"] || p["region"]) {
      if (p["target"]) r.fail(path + ".target", "is only allowed for a single-vertex pin");
      if (p["region"]) {
        pin.kind = PinSelector::Kind::kRegion;
        pin.region = readRegion(r, p["region"], path + ".region");
      } else {
        pin.kind = PinSelector::Kind::kEdge;
        pin.edge = r.word(p["edge"], path + ".edge");
        const std::string& e = pin.edge;
        if (e != "top" && e != "bottom" && e != "left" && e != "right" && e != "all") {
          r.fail(path + ".edge", "value '" + e + "' must be top, bottom, left, right or all");
        }
      }
    } else if (p["vertex"]) {
      pin.kind = PinSelector::Kind::kVertex;
      pin.vertex = r.integer(p["vertex"], path + ".vertex");
    } else {
      if (!p["row"] || !p["col"]) r.fail(path, "give both 'row' and 'col'");
      pin.kind = PinSelector::Kind::kCell;
      pin.row = r.integer(p["row"], path + ".row");
      pin.col = r.integer(p["col"], path + ".col");
    }
    if (p["target"]) pin.target = r.point(p["target"], path + ".target");
    scene.pins.push_back(std::move(pin));
  }
}

void readMeshColliders(const SceneFields& r, const YAML::Node& node, SceneConfig& scene) {
  if (!node.IsSequence()) r.fail("colliders.meshes", "must be a list");
  for (std::size_t k = 0; k < node.size(); ++k) {
    const std::string path = "colliders.meshes[" + std::to_string(k) + "]";
    const YAML::Node m = node[k];
    r.map(m, path, {"file", "position", "orientation_rpy", "scale", "thickness", "friction"});
    MeshColliderSpec spec;
    TriangleMesh mesh = readPlacedMesh(r, m, path, spec.file);
    double thickness = 0.005, friction = 0.0;
    if (m["thickness"]) {
      thickness = r.number(m["thickness"], path + ".thickness", settings::kMeshThickness);
    }
    if (m["friction"]) friction = r.number(m["friction"], path + ".friction", settings::kFriction);
    try {
      spec.obstacle = std::make_shared<const MeshObstacle>(std::move(mesh), thickness, friction);
    } catch (const std::invalid_argument& e) {
      r.fail(path + ".file", e.what());
    }
    scene.meshes.push_back(std::move(spec));
  }
}

void readColliders(const SceneFields& r, const YAML::Node& node, SceneConfig& scene) {
  r.map(node, "colliders", {"spheres", "meshes", "ground", "bodies"});
  if (node["meshes"]) readMeshColliders(r, node["meshes"], scene);
  if (node["bodies"]) readBodyColliders(r, node["bodies"], scene.bodies);
  if (const YAML::Node spheres = node["spheres"]) {
    if (!spheres.IsSequence()) r.fail("colliders.spheres", "must be a list");
    for (std::size_t k = 0; k < spheres.size(); ++k) {
      const std::string path = "colliders.spheres[" + std::to_string(k) + "]";
      const YAML::Node s = spheres[k];
      r.map(s, path, {"center", "radius", "velocity", "friction", "mass", "restitution"});
      if (!s["center"]) r.fail(path + ".center", "is required");
      if (!s["radius"]) r.fail(path + ".radius", "is required");
      SphereCollider sphere;
      sphere.center = r.point(s["center"], path + ".center");
      sphere.radius = r.number(s["radius"], path + ".radius", settings::kSphereRadius);
      if (s["velocity"]) sphere.velocity = r.vec3(s["velocity"], path + ".velocity");
      if (s["friction"]) {
        sphere.friction = r.number(s["friction"], path + ".friction", settings::kFriction);
      }
      if (s["mass"]) sphere.mass = r.number(s["mass"], path + ".mass", settings::kSphereMass);
      if (s["restitution"]) {
        sphere.restitution =
            r.number(s["restitution"], path + ".restitution", settings::kRestitution);
      }
      scene.spheres.push_back(sphere);
    }
  }
  if (const YAML::Node ground = node["ground"]) {
    r.map(ground, "colliders.ground", {"height", "friction"});
    scene.ground.enabled = true;
    if (ground["height"]) {
      scene.ground.height =
          r.number(ground["height"], "colliders.ground.height", settings::kCoordinate);
    }
    if (ground["friction"]) {
      scene.ground.friction =
          r.number(ground["friction"], "colliders.ground.friction", settings::kFriction);
    }
  }
}

/// self_collision: {enabled, mode, thickness, friction}; present = on unless enabled: false.
void readSelfCollision(const SceneFields& r, const YAML::Node& node, SelfContactSettings& self) {
  const std::string path = "self_collision";
  r.map(node, path, {"enabled", "mode", "thickness", "friction"});
  if (node["mode"]) {
    try {
      self.mode = selfContactModeFromName(r.word(node["mode"], path + ".mode"));
    } catch (const std::invalid_argument&) {
      r.fail(path + ".mode", "value " + SceneFields::show(node["mode"]) +
                                 " must be one of triangles, particles");
    }
  }
  self.enabled = true;
  if (node["enabled"]) self.enabled = r.boolean(node["enabled"], path + ".enabled");
  if (node["thickness"]) {
    self.thickness = r.number(node["thickness"], path + ".thickness", settings::kSelfThickness);
  }
  if (node["friction"]) {
    self.friction = r.number(node["friction"], path + ".friction", settings::kSelfFriction);
  }
}

}  // namespace

SceneConfig parseScene(const std::string& yaml_text, const std::string& source) {
  const SceneFields r(source);
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::Exception& e) {
    throw SceneError(source, "", std::string("YAML syntax error: ") + e.what());
  }
  if (!root.IsMap()) r.fail("", "a scene must be a YAML map of fields");
  r.map(root, "", {"name", "description", "time_step", "gravity", "solver", "cloth", "material",
                   "pins", "colliders", "divergence_strain", "self_collision"});

  SceneConfig scene;
  scene.source = source;
  if (root["name"]) scene.name = r.text(root["name"], "name");
  if (root["description"]) scene.description = r.text(root["description"], "description");
  if (root["time_step"]) {
    scene.time_step = r.number(root["time_step"], "time_step", settings::kTimeStep);
  }
  if (root["gravity"]) scene.gravity = r.vec3(root["gravity"], "gravity", &settings::kGravity);
  if (root["solver"]) readSolver(r, root["solver"], scene.options, scene.given);
  if (root["divergence_strain"]) {
    scene.options.divergence_strain =
        r.number(root["divergence_strain"], "divergence_strain", settings::kDivergenceStrain);
  }
  if (!root["cloth"]) r.fail("cloth", "is required");
  const YAML::Node cloth = root["cloth"];
  r.map(cloth, "cloth", {"grid", "mesh"});
  if (static_cast<bool>(cloth["grid"]) == static_cast<bool>(cloth["mesh"])) {
    r.fail("cloth", "give exactly one of 'grid' or 'mesh'");
  }
  if (cloth["grid"]) readGrid(r, cloth["grid"], scene.grid);
  else readClothMesh(r, cloth["mesh"], scene);
  if (!root["material"]) r.fail("material", "is required");
  readMaterial(r, root["material"], scene);
  if (root["pins"]) readPins(r, root["pins"], scene);
  if (root["colliders"]) readColliders(r, root["colliders"], scene);
  if (root["self_collision"]) {
    readSelfCollision(r, root["self_collision"], scene.options.self_contact);
  }
  return scene;
}

SceneConfig loadSceneFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw SceneError(path, "", "cannot open the file");
  std::stringstream text;
  text << in.rdbuf();
  SceneConfig scene = parseScene(text.str(), path);
  if (scene.name.empty()) {
    const auto slash = path.find_last_of('/');
    std::string stem = path.substr(slash == std::string::npos ? 0 : slash + 1);
    scene.name = stem.substr(0, stem.rfind('.'));
  }
  return scene;
}

}  // namespace cloth_sim
