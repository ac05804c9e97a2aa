#include "cloth_sim/node/urdf_colliders.h"

#include <memory>
#include <stdexcept>

#include <ros/package.h>
#include <urdf/model.h>

#include "cloth_sim/core/model/mesh_file.h"

namespace cloth_sim::node {
namespace {

Eigen::Isometry3d toIsometry(const urdf::Pose& p) {
  double x = 0, y = 0, z = 0, w = 1;
  p.rotation.getQuaternion(x, y, z, w);
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  out.translate(Vec3(p.position.x, p.position.y, p.position.z));
  out.rotate(Eigen::Quaterniond(w, x, y, z).normalized());
  return out;
}

BodyGeometry geometryOf(const urdf::Geometry& g, const std::string& where, double margin,
                        double friction, const MeshPathResolver& resolve) {
  BodyGeometry out;
  switch (g.type) {
    case urdf::Geometry::SPHERE:
      out.shape = BodyShape::kSphere;
      out.radius = static_cast<const urdf::Sphere&>(g).radius;
      break;
    case urdf::Geometry::BOX: {
      const urdf::Vector3& d = static_cast<const urdf::Box&>(g).dim;
      out.shape = BodyShape::kBox;
      out.size = Vec3(d.x, d.y, d.z);
      break;
    }
    case urdf::Geometry::CYLINDER: {
      const auto& c = static_cast<const urdf::Cylinder&>(g);
      out.shape = BodyShape::kCapsule;
      out.radius = c.radius;
      out.length = c.length;
      break;
    }
    case urdf::Geometry::MESH: {
      const auto& m = static_cast<const urdf::Mesh&>(g);
      if (m.scale.x != m.scale.y || m.scale.x != m.scale.z) {
        throw std::invalid_argument(where + ": mesh scale must be uniform");
      }
      const std::string path = resolve(m.filename);
      out.shape = BodyShape::kMesh;
      out.mesh = std::make_shared<const MeshObstacle>(
          loadMeshFile(path).transformed(Eigen::Isometry3d::Identity(), m.scale.x), margin, friction);
      break;
    }
  }
  return out;
}

}  // namespace

std::string resolveMeshUrl(const std::string& url) {
  const std::string package = "package://", file = "file://";
  if (url.compare(0, file.size(), file) == 0) return url.substr(file.size());
  if (url.compare(0, package.size(), package) != 0) return url;
  const std::size_t slash = url.find('/', package.size());
  const std::string name = url.substr(package.size(), slash - package.size());
  const std::string root = ros::package::getPath(name);
  if (root.empty()) throw std::invalid_argument("mesh '" + url + "': no package '" + name + "'");
  return root + (slash == std::string::npos ? "" : url.substr(slash));
}

std::vector<BodyCollider> urdfColliders(const std::string& urdf_xml,
                                        const std::vector<std::string>& links, double margin,
                                        double friction, const MeshPathResolver& resolve) {
  urdf::Model model;
  if (urdf_xml.empty()) throw std::invalid_argument("the robot description is empty");
  if (!model.initString(urdf_xml)) {
    throw std::invalid_argument("the robot description is not a URDF that parses");
  }
  std::vector<BodyCollider> out;
  for (const std::string& name : links) {
    const urdf::LinkConstSharedPtr link = model.getLink(name);
    if (!link) throw std::invalid_argument("link '" + name + "' is not in the robot description");
    if (link->collision_array.empty()) {
      throw std::invalid_argument("link '" + name + "' has no <collision> geometry");
    }
    for (std::size_t k = 0; k < link->collision_array.size(); ++k) {
      const urdf::CollisionSharedPtr& c = link->collision_array[k];
      const std::string where = "link '" + name + "' collision " + std::to_string(k);
      if (!c || !c->geometry) throw std::invalid_argument(where + " has no geometry");
      BodyCollider b;
      b.name = name;
      b.follows_frame = true;
      b.margin = margin;
      b.friction = friction;
      try {
        b.geometry = geometryOf(*c->geometry, where, margin, friction, resolve);
        b.origin = toIsometry(c->origin);
        BodySet().add(b);  // the set's checks (sizes, margin, friction), named here
      } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(where + ": " + e.what());
      }
      out.push_back(std::move(b));
    }
  }
  return out;
}

}  // namespace cloth_sim::node
