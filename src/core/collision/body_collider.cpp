#include "cloth_sim/core/collision/body_collider.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "cloth_sim/core/settings/settings_table.h"

namespace cloth_sim {
namespace {

/// The point of the capsule's segment (from -length/2 to +length/2 along z) nearest to @p p.
Vec3 capsuleAxisPoint(const BodyGeometry& g, const Vec3& p) {
  const double half = 0.5 * g.length;
  return Vec3(0.0, 0.0, std::clamp(p.z(), -half, half));
}

bool finitePose(const Eigen::Isometry3d& pose) { return pose.matrix().allFinite(); }

void checkBody(const BodyCollider& b) {
  const BodyGeometry& g = b.geometry;
  const std::string what = std::string(bodyShapeName(g.shape)) + " collider";
  switch (g.shape) {
    case BodyShape::kSphere:
      settings::kBodySize.require(g.radius, what + " radius");
      break;
    case BodyShape::kCapsule:
      settings::kBodySize.require(g.radius, what + " radius");
      settings::kCapsuleLength.require(g.length, what + " length");
      break;
    case BodyShape::kBox:
      for (int k = 0; k < 3; ++k) settings::kBodySize.require(g.size[k], what + " size");
      break;
    case BodyShape::kMesh:
      if (!g.mesh || g.mesh->mesh().triangleCount() == 0) {
        throw std::invalid_argument(what + ": the mesh has no triangle");
      }
      break;
  }
  settings::kBodyMargin.require(b.margin, what + " margin");
  settings::kFriction.require(b.friction, what + " friction");
  if (!finitePose(b.origin)) throw std::invalid_argument(what + " origin must be finite");
  if (!finitePose(b.frame_pose)) throw std::invalid_argument(what + " pose must be finite");
}

}  // namespace

const char* bodyShapeName(BodyShape shape) {
  switch (shape) {
    case BodyShape::kSphere: return "sphere";
    case BodyShape::kCapsule: return "capsule";
    case BodyShape::kBox: return "box";
    case BodyShape::kMesh: return "mesh";
  }
  return "?";
}

BodyShape bodyShapeFromName(const std::string& name) {
  for (BodyShape s : {BodyShape::kSphere, BodyShape::kCapsule, BodyShape::kBox, BodyShape::kMesh}) {
    if (name == bodyShapeName(s)) return s;
  }
  throw std::invalid_argument("shape '" + name.substr(0, 64) +
                              "' must be one of sphere, capsule, box, mesh");
}

double BodyGeometry::distance(const Vec3& p) const {
  switch (shape) {
    case BodyShape::kSphere: return p.norm() - radius;
    case BodyShape::kCapsule: return (p - capsuleAxisPoint(*this, p)).norm() - radius;
    case BodyShape::kBox: {
      const Vec3 q = p.cwiseAbs() - 0.5 * size;
      return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
    }
    case BodyShape::kMesh: return 0.0;
  }
  return 0.0;
}

Vec3 BodyGeometry::gradient(const Vec3& p) const {
  Vec3 d = Vec3::Zero();
  switch (shape) {
    case BodyShape::kSphere: d = p; break;
    case BodyShape::kCapsule: d = p - capsuleAxisPoint(*this, p); break;
    case BodyShape::kBox: {
      const Vec3 q = p.cwiseAbs() - 0.5 * size;
      if (q.maxCoeff() > 0.0) {
        d = q.cwiseMax(0.0).cwiseProduct(p.cwiseSign());  // outside: towards the nearest point
      } else {
        Eigen::Index axis = 0;
        q.maxCoeff(&axis);  // inside: out through the nearest face
        d[axis] = p[axis] >= 0.0 ? 1.0 : -1.0;
      }
      break;
    }
    case BodyShape::kMesh: break;
  }
  const double n = d.norm();
  return n > 1e-15 ? Vec3(d / n) : Vec3::UnitZ();
}

double BodyGeometry::boundingRadius() const {
  switch (shape) {
    case BodyShape::kSphere: return radius;
    case BodyShape::kCapsule: return radius + 0.5 * length;
    case BodyShape::kBox: return 0.5 * size.norm();
    case BodyShape::kMesh: {
      if (!mesh) return 0.0;
      return mesh->mesh().vertices.colwise().norm().maxCoeff() + mesh->thickness();
    }
  }
  return 0.0;
}

int BodySet::add(const BodyCollider& body) {
  BodyCollider b = body;
  if (b.geometry.shape == BodyShape::kMesh && b.geometry.mesh) {
    b.margin = b.geometry.mesh->thickness();  // the mesh obstacle's own
    b.friction = b.geometry.mesh->friction();
  }
  checkBody(b);
  b.id = next_id_++;
  b.previous_frame_pose = b.frame_pose;
  b.placed = !b.follows_frame;
  bodies_.push_back(std::move(b));
  return bodies_.back().id;
}

void BodySet::remove(int id) {
  auto it = std::find_if(bodies_.begin(), bodies_.end(), [id](const BodyCollider& b) { return b.id == id; });
  if (it == bodies_.end()) throw std::invalid_argument("no collider with id " + std::to_string(id));
  bodies_.erase(it);
}

void BodySet::setFramePose(int id, const Eigen::Isometry3d& frame_pose) {
  auto it = std::find_if(bodies_.begin(), bodies_.end(), [id](const BodyCollider& b) { return b.id == id; });
  if (it == bodies_.end()) throw std::invalid_argument("no collider with id " + std::to_string(id));
  if (!finitePose(frame_pose)) throw std::invalid_argument("collider pose must be finite");
  it->frame_pose = frame_pose;
  it->previous_frame_pose = frame_pose;
  it->placed = true;
}

const BodyCollider* BodySet::find(int id) const {
  auto it = std::find_if(bodies_.begin(), bodies_.end(), [id](const BodyCollider& b) { return b.id == id; });
  return it == bodies_.end() ? nullptr : &*it;
}

void BodySet::place(double time, const BodyPoseSource& source) {
  for (BodyCollider& b : bodies_) {
    b.previous_frame_pose = b.frame_pose;
    if (!b.follows_frame || !source) continue;
    const Eigen::Isometry3d pose = source(b.id, time);
    if (!finitePose(pose)) continue;
    b.frame_pose = pose;
    if (!b.placed) b.previous_frame_pose = pose;
    b.placed = true;
  }
}

void BodySet::settle() {
  for (BodyCollider& b : bodies_) b.previous_frame_pose = b.frame_pose;
}

}  // namespace cloth_sim
