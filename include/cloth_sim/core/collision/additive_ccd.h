/// @file additive_ccd.h
/// Continuous collision detection of two moving mesh primitives by conservative advancement:
/// additive CCD (ACCD) of Li, Kaufman and Jiang 2021, "Codimensional Incremental Potential
/// Contact", section 4 (docs/method.md, "Self-contact").
#pragma once

#include <array>

#include "cloth_sim/core/collision/primitive_distance.h"
#include "cloth_sim/core/linalg/types.h"

namespace cloth_sim {

/// The two kinds of primitive pair whose contact triangle self-contact handles: a vertex and a
/// triangle (vertices 0; 1, 2, 3), two edges (vertices 0, 1; 2, 3).
enum class PairKind : unsigned char { kVertexTriangle, kEdgeEdge };

/// Four positions (m) of a pair's vertices, in the order of PairKind.
using PairPoints = std::array<Vec3, 4>;

/// Closest points of the pair @p kind at @p x (pointTriangle or segmentSegment).
ClosestPoints closestPoints(PairKind kind, const PairPoints& x);

/// What additiveCcd found.
struct CcdResult {
  /// Largest time (fraction of the motion, in [0, 1]) up to which the distance is proven to stay
  /// above the minimum distance; 1 = the whole motion is safe.
  double safe_time = 1.0;
  int iterations = 0;  ///< distance evaluations after the first
};

/// Additive CCD: moves the pair from @p x0 along @p motion (each vertex linearly, x0 + s motion,
/// s in [0, 1]) and returns how far it can go while its distance stays above @p min_distance
/// (m, >= 0).
///
/// The common motion (the mean of the four) is removed; then no point of the pair can approach
/// the other primitive faster than l = max |motion| of one side + that of the other (a point of
/// a primitive moves a weighted mean of its vertices' motions), so from a distance d the pair
/// can advance (d - min_distance) / l without reaching min_distance. ACCD advances by 0.9 of
/// that, measures the distance again and repeats; it stops with a collision when the gap
/// d - min_distance has fallen below 1 % of its start (the safe time is then just before the
/// impact) or after @p max_iterations advances (conservative: the time reached so far). Exact in
/// exact arithmetic; rounding is covered by the 10 % kept at each advance.
CcdResult additiveCcd(PairKind kind, const PairPoints& x0, const PairPoints& motion,
                      double min_distance, int max_iterations = 100);

}  // namespace cloth_sim
