#include "cloth_sim/node/body_messages.h"

#include <cmath>
#include <memory>
#include <stdexcept>

#include <tf2_eigen/tf2_eigen.h>

#include "cloth_sim/core/model/mesh_file.h"
#include "cloth_sim/core/settings/settings_table.h"
#include "cloth_sim/node/conversions.h"
#include "cloth_sim/node/names.h"

namespace cloth_sim::node {
namespace {

constexpr int kCapIds = 1000000;  ///< a capsule's caps: id + 1e6 and id + 2e6

Eigen::Isometry3d originOf(const geometry_msgs::Pose& p) {
  const Vec3 t = toVec3(p.position);
  const Eigen::Vector4d q(p.orientation.x, p.orientation.y, p.orientation.z, p.orientation.w);
  requireFinite(t, "origin.position");
  if (!q.allFinite()) throw std::invalid_argument("origin.orientation must be finite");
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  out.translate(t);
  if (q.norm() == 0.0) return out;  // unset: identity
  if (std::abs(q.norm() - 1.0) > 1e-3) {
    throw std::invalid_argument("origin.orientation must be a unit quaternion (norm " +
                                std::to_string(q.norm()) + ")");
  }
  out.rotate(Eigen::Quaterniond(q[3], q[0], q[1], q[2]).normalized());
  return out;
}

visualization_msgs::Marker shapeMarker(const BodyCollider& b, int id, int type,
                                       const std_msgs::Header& header) {
  visualization_msgs::Marker m;
  m.header = header;
  m.ns = names::kBodiesNs;
  m.id = id;
  m.type = type;
  m.action = visualization_msgs::Marker::ADD;
  m.pose = tf2::toMsg(b.pose());
  m.color.r = 0.55f;
  m.color.g = 0.7f;
  m.color.b = 0.55f;
  m.color.a = 0.8f;
  return m;
}

}  // namespace

BodyCollider bodyFromRequest(const AddCollider::Request& req, const MeshPathResolver& resolve) {
  BodyCollider b;
  b.margin = req.margin == 0.0 ? 0.005 : req.margin;
  b.friction = req.friction;
  settings::kBodyMargin.require(b.margin, "margin");
  settings::kFriction.require(b.friction, "friction");
  b.geometry.shape = bodyShapeFromName(req.shape);
  b.geometry.radius = req.radius;
  b.geometry.length = req.length;
  b.geometry.size = toVec3(req.size);
  if (b.geometry.shape == BodyShape::kMesh) {
    if (req.mesh_file.empty()) throw std::invalid_argument("mesh_file is empty: name an OBJ or STL file");
    const double scale = req.mesh_scale == 0.0 ? 1.0 : req.mesh_scale;
    settings::kMeshScale.require(scale, "mesh_scale");
    b.geometry.mesh = std::make_shared<const MeshObstacle>(
        loadMeshFile(resolve(req.mesh_file)).transformed(Eigen::Isometry3d::Identity(), scale),
        b.margin, b.friction);
  }
  b.origin = originOf(req.origin);
  b.name = req.name;
  BodySet().add(b);  // the core's checks of the sizes
  return b;
}

ColliderInfo toColliderInfo(const BodyCollider& b, const std::string& frame_id, bool stale) {
  ColliderInfo info;
  info.id = b.id;
  info.name = b.name;
  info.shape = bodyShapeName(b.geometry.shape);
  info.frame_id = frame_id;
  info.pose = tf2::toMsg(b.pose());
  info.radius = b.geometry.radius;
  info.length = b.geometry.length;
  info.size = toVector3Msg(b.geometry.size);
  info.margin = b.margin;
  info.friction = b.friction;
  info.frame_stale = stale || !b.placed;
  return info;
}

void appendBodyMarkers(const std::vector<BodyCollider>& bodies, const std_msgs::Header& header,
                       std::set<int>& shown, visualization_msgs::MarkerArray& out) {
  std::set<int> now;
  using visualization_msgs::Marker;
  for (const BodyCollider& b : bodies) {
    if (!b.placed || !b.pose().matrix().allFinite()) continue;
    const BodyGeometry& g = b.geometry;
    switch (g.shape) {
      case BodyShape::kSphere: {
        Marker m = shapeMarker(b, b.id, Marker::SPHERE, header);
        m.scale.x = m.scale.y = m.scale.z = 2.0 * g.radius;
        out.markers.push_back(m);
        break;
      }
      case BodyShape::kCapsule: {
        Marker m = shapeMarker(b, b.id, Marker::CYLINDER, header);
        m.scale.x = m.scale.y = 2.0 * g.radius;
        m.scale.z = std::max(g.length, 1e-6);
        out.markers.push_back(m);
        for (int end : {1, 2}) {
          Marker cap = shapeMarker(b, end * kCapIds + b.id, Marker::SPHERE, header);
          const Vec3 c = b.pose() * Vec3(0, 0, (end == 1 ? 0.5 : -0.5) * g.length);
          cap.pose.position = toPointMsg(c);
          cap.scale.x = cap.scale.y = cap.scale.z = 2.0 * g.radius;
          out.markers.push_back(cap);
          now.insert(end * kCapIds + b.id);
        }
        break;
      }
      case BodyShape::kBox: {
        Marker m = shapeMarker(b, b.id, Marker::CUBE, header);
        m.scale.x = g.size.x();
        m.scale.y = g.size.y();
        m.scale.z = g.size.z();
        out.markers.push_back(m);
        break;
      }
      case BodyShape::kMesh: {
        Marker m = shapeMarker(b, b.id, Marker::TRIANGLE_LIST, header);
        m.scale.x = m.scale.y = m.scale.z = 1.0;
        const TriangleMesh& mesh = g.mesh->mesh();
        for (int t = 0; t < mesh.triangleCount(); ++t)
          for (int c = 0; c < 3; ++c) m.points.push_back(toPointMsg(mesh.vertices.col(mesh.triangles(c, t))));
        out.markers.push_back(m);
        break;
      }
    }
    now.insert(b.id);
  }
  for (int id : shown) {
    if (now.count(id)) continue;
    Marker m;
    m.header = header;
    m.ns = names::kBodiesNs;
    m.id = id;
    m.action = Marker::DELETE;
    out.markers.push_back(m);
  }
  shown = std::move(now);
}

}  // namespace cloth_sim::node
