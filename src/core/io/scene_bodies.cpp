#include "cloth_sim/core/io/scene_bodies.h"

#include <memory>
#include <stdexcept>

#include "cloth_sim/core/model/mesh_file.h"
#include "cloth_sim/core/settings/settings_table.h"

namespace cloth_sim {
namespace {

/// The geometry of body @p node at @p path.
BodyGeometry readGeometry(const SceneFields& r, const YAML::Node& node, const std::string& path,
                          double margin, double friction) {
  BodyGeometry g;
  if (!node["shape"]) r.fail(path + ".shape", "is required (sphere, capsule, box or mesh)");
  try {
    g.shape = bodyShapeFromName(r.word(node["shape"], path + ".shape"));
  } catch (const std::invalid_argument& e) {
    r.fail(path + ".shape", e.what());
  }
  const auto need = [&](const char* key) {
    if (!node[key]) r.fail(path + "." + key, std::string("is required for a ") + bodyShapeName(g.shape));
    return node[key];
  };
  switch (g.shape) {
    case BodyShape::kSphere:
      g.radius = r.number(need("radius"), path + ".radius", settings::kBodySize);
      break;
    case BodyShape::kCapsule:
      g.radius = r.number(need("radius"), path + ".radius", settings::kBodySize);
      g.length = r.number(need("length"), path + ".length", settings::kCapsuleLength);
      break;
    case BodyShape::kBox: {
      const Vec3 size = r.vec3(need("size"), path + ".size");
      for (int k = 0; k < 3; ++k) {
        if (!settings::kBodySize.allows(size[k])) {
          r.fail(path + ".size", settings::kBodySize.refusal(size[k], "value"));
        }
      }
      g.size = size;
      break;
    }
    case BodyShape::kMesh: {
      const std::string file = r.resolve(r.text(need("file"), path + ".file"));
      double scale = 1.0;
      if (node["scale"]) scale = r.number(node["scale"], path + ".scale", settings::kMeshScale);
      try {
        TriangleMesh mesh = loadMeshFile(file).transformed(Eigen::Isometry3d::Identity(), scale);
        g.mesh = std::make_shared<const MeshObstacle>(std::move(mesh), margin, friction);
      } catch (const std::invalid_argument& e) {
        r.fail(path + ".file", e.what());
      }
      break;
    }
  }
  return g;
}

}  // namespace

Eigen::Isometry3d readScenePose(const SceneFields& r, const YAML::Node& node,
                                const std::string& path) {
  Vec3 position = Vec3::Zero(), rpy = Vec3::Zero();
  if (node["position"]) position = r.point(node["position"], path + ".position");
  if (node["orientation_rpy"]) rpy = r.vec3(node["orientation_rpy"], path + ".orientation_rpy");
  return Eigen::Translation3d(position) * Eigen::AngleAxisd(rpy.z(), Vec3::UnitZ()) *
         Eigen::AngleAxisd(rpy.y(), Vec3::UnitY()) * Eigen::AngleAxisd(rpy.x(), Vec3::UnitX());
}

void readBodyColliders(const SceneFields& r, const YAML::Node& node, std::vector<BodyCollider>& out) {
  if (!node.IsSequence()) r.fail("colliders.bodies", "must be a list");
  for (std::size_t k = 0; k < node.size(); ++k) {
    const std::string path = "colliders.bodies[" + std::to_string(k) + "]";
    const YAML::Node b = node[k];
    r.map(b, path, {"shape", "name", "frame", "radius", "length", "size", "file", "scale",
                    "position", "orientation_rpy", "margin", "friction"});
    BodyCollider body;
    if (b["margin"]) body.margin = r.number(b["margin"], path + ".margin", settings::kBodyMargin);
    if (b["friction"]) body.friction = r.number(b["friction"], path + ".friction", settings::kFriction);
    body.geometry = readGeometry(r, b, path, body.margin, body.friction);
    const Eigen::Isometry3d pose = readScenePose(r, b, path);
    if (b["name"]) body.name = r.text(b["name"], path + ".name");
    if (b["frame"]) {
      body.name = r.text(b["frame"], path + ".frame");
      if (body.name.empty()) r.fail(path + ".frame", "must name a frame");
      body.follows_frame = true;
      body.origin = pose;
    } else {
      body.frame_pose = pose;
    }
    try {
      BodySet().add(body);  // the set's own checks, reported on this entry
    } catch (const std::invalid_argument& e) {
      r.fail(path, e.what());
    }
    out.push_back(std::move(body));
  }
}

}  // namespace cloth_sim
