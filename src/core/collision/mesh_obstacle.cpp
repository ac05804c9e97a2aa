#include "cloth_sim/core/collision/mesh_obstacle.h"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "cloth_sim/core/collision/contact_projection.h"
#include "cloth_sim/core/settings/settings_table.h"

namespace cloth_sim {
namespace {

double meanEdgeLength(const TriangleMesh& mesh) {
  double sum = 0.0;
  for (int t = 0; t < mesh.triangleCount(); ++t)
    for (int k = 0; k < 3; ++k)
      sum += (mesh.vertices.col(mesh.triangles(k, t)) -
              mesh.vertices.col(mesh.triangles((k + 1) % 3, t))).norm();
  return sum / (3.0 * mesh.triangleCount());
}

}  // namespace

MeshObstacle::MeshObstacle(TriangleMesh mesh, double thickness, double friction,
                           double cell_size)
    : mesh_(std::move(mesh)), thickness_(thickness), friction_(friction) {
  settings::kMeshThickness.require(thickness, "mesh obstacle thickness");
  settings::kFriction.require(friction, "mesh obstacle friction");
  if (mesh_.triangleCount() == 0 || !mesh_.vertices.allFinite()) {
    throw std::invalid_argument("mesh obstacle needs at least one triangle and finite vertices");
  }
  normals_.resize(mesh_.triangleCount());
  for (int t = 0; t < mesh_.triangleCount(); ++t) {
    const Vec3 a = mesh_.vertices.col(mesh_.triangles(0, t));
    const Vec3 n = (mesh_.vertices.col(mesh_.triangles(1, t)) - a)
                       .cross(mesh_.vertices.col(mesh_.triangles(2, t)) - a);
    if (!(n.norm() > 0.0)) {
      throw std::invalid_argument("mesh obstacle triangle " + std::to_string(t) + " is degenerate");
    }
    normals_[t] = n.normalized();
  }
  grid_ = SpatialHash(cell_size > 0.0 ? cell_size
                                      : std::max(meanEdgeLength(mesh_), 2.0 * thickness_));
  boxes_.reserve(mesh_.triangleCount());
  for (int t = 0; t < mesh_.triangleCount(); ++t) {
    boxes_.push_back(triangleBox(t));
    bounds_.extend(boxes_.back());
    grid_.insert(t, boxes_.back());
  }
}

Eigen::AlignedBox3d MeshObstacle::triangleBox(int t) const {
  Eigen::AlignedBox3d box;
  for (int k = 0; k < 3; ++k) box.extend(Vec3(mesh_.vertices.col(mesh_.triangles(k, t))));
  return box;
}

template <typename Visit>
void MeshObstacle::forTrianglesNear(const Eigen::AlignedBox3d& box, Visit&& visit,
                                    int* candidates) const {
  if (!bounds_.intersects(box)) return;
  grid_.query(box, [&](int t) {
    if (candidates != nullptr) ++*candidates;
    if (boxes_[t].intersects(box)) visit(t);  // else a large triangle's cell, not the triangle
  });
}

bool MeshObstacle::clear(const Vec3& a, const Vec3& b) const {
  Eigen::AlignedBox3d box;
  box.extend(a).extend(b);
  box.min().array() -= thickness_;
  box.max().array() += thickness_;
  bool hit = false;
  forTrianglesNear(box, [&](int t) {
    if (hit) return;
    const Vec3 p = mesh_.vertices.col(mesh_.triangles(0, t));
    const Vec3 q = mesh_.vertices.col(mesh_.triangles(1, t));
    const Vec3 r = mesh_.vertices.col(mesh_.triangles(2, t));
    hit = segmentTriangleCrossing(a, b, p, q, r) >= 0.0 ||
          (b - closestPointOnTriangle(b, p, q, r)).norm() < thickness_;
  });
  return !hit;
}

bool MeshObstacle::collide(const Vec3& start, Vec3& end, const std::optional<Vec3>& free_motion,
                           Vec3* contact_normal) const {
  bool changed = false;
  last_candidates_ = 0;
  const Vec3 wanted = end;
  // A few passes: a correction by one triangle may bring the particle near another (a corner).
  for (int pass = 0; pass < 3; ++pass) {
    Eigen::AlignedBox3d box;
    box.extend(start).extend(end);
    box.min().array() -= thickness_;
    box.max().array() += thickness_;
    double first_crossing = std::numeric_limits<double>::infinity();
    int crossed = -1;
    int nearest = -1;
    double nearest_gap = 0.0;  // thickness minus distance, > 0 when too close
    Vec3 nearest_point = Vec3::Zero();
    forTrianglesNear(box, [&](int t) {
      const Vec3 a = mesh_.vertices.col(mesh_.triangles(0, t));
      const Vec3 b = mesh_.vertices.col(mesh_.triangles(1, t));
      const Vec3 c = mesh_.vertices.col(mesh_.triangles(2, t));
      const double s = segmentTriangleCrossing(start, end, a, b, c);
      if (s >= 0.0 && s < first_crossing) {
        first_crossing = s;
        crossed = t;
      }
      const Vec3 q = closestPointOnTriangle(end, a, b, c);
      const double gap = thickness_ - (end - q).norm();
      if (gap > nearest_gap) {
        nearest_gap = gap;
        nearest = t;
        nearest_point = q;
      }
    }, &last_candidates_);
    Vec3 normal;
    double correction = 0.0;
    if (crossed >= 0) {
      // Went through triangle `crossed`: back to the start side, thickness above its plane.
      const Vec3 a = mesh_.vertices.col(mesh_.triangles(0, crossed));
      normal = normals_[crossed];
      if ((start - a).dot(normal) < 0.0) normal = -normal;
      correction = thickness_ - (end - a).dot(normal);
    } else if (nearest >= 0) {
      // Too close to triangle `nearest` (its face, edge or corner): out along the gap.
      const Vec3 away = end - nearest_point;
      Vec3 side = normals_[nearest];
      const Vec3 a = mesh_.vertices.col(mesh_.triangles(0, nearest));
      if ((start - a).dot(side) < 0.0) side = -side;
      normal = (away.norm() > 1e-12 && away.dot(side) > 0.0) ? Vec3(away.normalized()) : side;
      correction = thickness_ - away.dot(normal);
    } else {
      break;
    }
    const Vec3 pushed = end + correction * normal;
    end = start + applyFriction(pushed - start, normal, frictionLoad(correction, normal, free_motion), friction_);
    changed = true;
    if (contact_normal != nullptr) *contact_normal = normal;
    // A straight path that only clipped an edge: when the slid particle reaches the wanted end
    // in a straight line without crossing or touching the mesh, it went round the edge (else a
    // particle pulled over a box's top edge would hook under it, step after step).
    if (crossed >= 0 && clear(end, wanted)) {
      end = wanted;
      break;
    }
  }
  return changed;
}

bool MeshObstacle::nearest(const Vec3& p, double reach, Vec3& point, Vec3& normal) const {
  Eigen::AlignedBox3d box(p);
  box.min().array() -= reach;
  box.max().array() += reach;
  double best = reach;
  forTrianglesNear(box, [&](int t) {
    const Vec3 q = closestPointOnTriangle(p, mesh_.vertices.col(mesh_.triangles(0, t)),
                                          mesh_.vertices.col(mesh_.triangles(1, t)),
                                          mesh_.vertices.col(mesh_.triangles(2, t)));
    const double d = (p - q).norm();
    if (d < best) {
      best = d;
      point = q;
    }
  });
  if (!(best < reach) || best < 1e-12) return false;
  normal = (p - point) / best;
  return true;
}

double MeshObstacle::distance(const Vec3& p) const {
  double best = std::numeric_limits<double>::infinity();
  for (int t = 0; t < mesh_.triangleCount(); ++t) {
    const Vec3 q = closestPointOnTriangle(p, mesh_.vertices.col(mesh_.triangles(0, t)),
                                          mesh_.vertices.col(mesh_.triangles(1, t)),
                                          mesh_.vertices.col(mesh_.triangles(2, t)));
    best = std::min(best, (p - q).norm());
  }
  return best;
}

}  // namespace cloth_sim
