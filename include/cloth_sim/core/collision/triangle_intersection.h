/// @file triangle_intersection.h
/// Exact triangle-triangle intersection and a counter of the intersecting pairs of one cloth:
/// the check that a run did not pass through itself (docs/method.md, "Self-contact").
#pragma once

#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "cloth_sim/core/collision/cell_hash.h"
#include "cloth_sim/core/linalg/types.h"

namespace cloth_sim {

/// True when segment pq crosses triangle abc: p and q strictly on opposite sides of its plane
/// and the crossing strictly inside it. Decided by the signs of orientation determinants
/// (orient3d), a determinant within double rounding (1e-12 relative) counting as zero: a segment
/// that only touches the triangle or lies in its plane (up to rounding) does not cross it.
bool segmentCrossesTriangle(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b,
                            const Vec3& c);

/// True when triangles (a0, a1, a2) and (b0, b1, b2) intersect: an edge of one crosses the other
/// (segmentCrossesTriangle). Two non-coplanar triangles intersect in a segment whose ends lie on
/// edges, so this is exact for them up to rounding; touching and coplanar overlaps count as no
/// intersection (a cloth never lies in itself without crossing somewhere else first).
bool trianglesIntersect(const Vec3& a0, const Vec3& a1, const Vec3& a2, const Vec3& b0,
                        const Vec3& b1, const Vec3& b2);

/// Counts the pairs of triangles of one surface that share no vertex and intersect.
///
/// Candidate pairs come from a CellHash of the triangles' boxes (key: the box's min corner, cell:
/// twice the mean box size); a triangle larger than a cell (a badly stretched one) is tested
/// against every triangle instead, so the count is exact whatever the shape. O(T) for T
/// triangles of similar size.
class IntersectionCounter {
 public:
  /// @p triangles: vertex indices, one column per triangle.
  explicit IntersectionCounter(Eigen::Matrix3Xi triangles);
  /// Number of intersecting pairs of non-adjacent triangles at @p positions (m); 0 when the
  /// positions are not finite (a frame the simulation rolls back).
  int count(const Points& positions) { return static_cast<int>(find(positions, nullptr)); }
  /// The intersecting pairs (first < second), for tests and diagnostics.
  std::vector<std::pair<int, int>> pairs(const Points& positions);
  /// Threads of the search (fixed blocks of triangles: the same count and pairs for any count).
  void setThreads(int threads) { threads_ = threads; }

 private:
  std::size_t find(const Points& positions, std::vector<std::pair<int, int>>* out);
  bool adjacent(int s, int t) const;
  bool intersect(const Points& x, int s, int t) const;

  Eigen::Matrix3Xi triangles_;
  std::vector<Eigen::AlignedBox3d> boxes_;
  Points keys_;
  std::vector<int> oversize_;
  std::vector<char> is_oversize_;
  CellHash hash_;
  int threads_ = 1;
};

}  // namespace cloth_sim
