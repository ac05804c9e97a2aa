/// @file primitive_distance.h
/// Closest points between the primitives of a triangle mesh: a point and a triangle, two
/// segments. The contact features of triangle self-contact (docs/method.md, "Self-contact"),
/// written so that one contact is a weighted sum of four vertices.
#pragma once

#include <array>

#include "cloth_sim/core/linalg/types.h"

namespace cloth_sim {

/// The closest points of two primitives as weights of their four vertices: the gap vector is
/// sum_k weight[k] x_k (the first primitive's closest point minus the second's), so the weights
/// sum to 0; distance = |gap| (m).
///
/// Point-triangle (p; a, b, c): weights (1, -u, -v, -w), (u, v, w) the barycentric coordinates
/// of the triangle's closest point. Segment-segment (p0, p1; q0, q1): weights
/// (1 - s, s, -(1 - r), -r), s and r the parameters of the closest points.
struct ClosestPoints {
  std::array<double, 4> weight{};
  double distance = 0.0;  ///< m
};

/// Closest points of point @p p and triangle (@p a, @p b, @p c) (Ericson 2004, "Real-Time
/// Collision Detection", 5.1.5, with the barycentric weights kept). A degenerate triangle (a
/// segment or a point) gives its closest point too.
ClosestPoints pointTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

/// Closest points of segments (@p p0, @p p1) and (@p q0, @p q1) (Ericson 2004, 5.1.9): parallel
/// and degenerate (zero-length) segments give one of their closest pairs.
ClosestPoints segmentSegment(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1);

/// The gap vector sum_k weight[k] x_k of @p c at the positions @p x0 .. @p x3 (m).
inline Vec3 gapVector(const ClosestPoints& c, const Vec3& x0, const Vec3& x1, const Vec3& x2,
                      const Vec3& x3) {
  return c.weight[0] * x0 + c.weight[1] * x1 + c.weight[2] * x2 + c.weight[3] * x3;
}

}  // namespace cloth_sim
