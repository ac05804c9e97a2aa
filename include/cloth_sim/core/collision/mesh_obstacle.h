/// @file mesh_obstacle.h
/// A static triangle-mesh obstacle (a table, a mannequin) for cloth particles.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "cloth_sim/core/collision/spatial_hash.h"
#include "cloth_sim/core/model/triangle_mesh.h"

namespace cloth_sim {

/// A still triangle mesh that particles cannot pass through and stay at least @c thickness
/// away from. Works for open surfaces and closed solids alike: a particle is kept on the side it
/// came from. Triangles live in a SpatialHash with cells about one mean edge long, so one
/// particle's query touches O(1) triangles and a step costs O(particles).
class MeshObstacle {
 public:
  /// @p mesh in world coordinates (m); @p thickness > 0 m; @p friction (Coulomb mu) >= 0;
  /// @p cell_size of the hash grid (m), 0 = the larger of the mean edge and 2 * thickness.
  /// Throws std::invalid_argument on a bad value or a mesh with a degenerate triangle.
  MeshObstacle(TriangleMesh mesh, double thickness, double friction, double cell_size = 0.0);

  /// Response for one particle that moved from @p start to @p end (m) during a step:
  /// if its path crossed a triangle, or it ended closer than thickness to one, @p end is put
  /// back on the start side at distance thickness, keeping the tangential part of the motion
  /// minus Coulomb friction. Friction presses with frictionLoad(correction, normal,
  /// @p free_motion) (the particle's free motion h v + h^2 g, when known). Returns true if
  /// @p end changed.
  /// @p normal, when given, gets the unit normal of the last correction (from the mesh to the
  /// particle).
  bool collide(const Vec3& start, Vec3& end, const std::optional<Vec3>& free_motion = std::nullopt,
               Vec3* normal = nullptr) const;

  /// The mesh point @p point nearest to @p p among the triangles within @p reach (m) of it, and
  /// the unit direction @p normal from that point to @p p (a face normal, or radial round an
  /// edge or corner). False if no triangle is that close or @p p lies on the mesh.
  bool nearest(const Vec3& p, double reach, Vec3& point, Vec3& normal) const;

  /// Distance (m) from @p p to the nearest triangle (brute force: for tests and checks).
  double distance(const Vec3& p) const;

  const TriangleMesh& mesh() const { return mesh_; }
  double thickness() const { return thickness_; }
  double friction() const { return friction_; }
  /// Triangles tested by the last collide() call (how much the hash grid pruned).
  int lastCandidates() const { return last_candidates_; }

 private:
  Eigen::AlignedBox3d triangleBox(int t) const;
  /// Calls @p visit(t) for each triangle t whose box meets @p box: none when @p box misses the
  /// mesh's bounds, else the hash grid's candidates (added to @p candidates when given) that
  /// pass the box test.
  template <typename Visit>
  void forTrianglesNear(const Eigen::AlignedBox3d& box, Visit&& visit,
                        int* candidates = nullptr) const;
  /// True when the segment @p a -> @p b crosses no triangle and @p b is at least thickness
  /// away from every triangle.
  bool clear(const Vec3& a, const Vec3& b) const;

  TriangleMesh mesh_;
  std::vector<Vec3> normals_;  ///< unit normal of each triangle (any orientation)
  std::vector<Eigen::AlignedBox3d> boxes_;  ///< bounding box of each triangle
  Eigen::AlignedBox3d bounds_;               ///< of the whole mesh: queries away from it end early
  double thickness_;
  double friction_;
  SpatialHash grid_;
  mutable int last_candidates_ = 0;
};

}  // namespace cloth_sim
