/// @file contour_untangling.h
/// Recovery of a cloth that passes through itself: intersection contour minimization (Volino
/// and Magnenat-Thalmann 2006, "Resolving surface collisions through intersection contour
/// minimization"). Where two triangles intersect, the cloth is moved so that the curve along
/// which it intersects itself gets shorter; a closed curve shrinks to nothing and one that ends
/// on the cloth's border slides off it (docs/method.md, "Self-contact", "Tangles").
#pragma once

#include <utility>
#include <vector>

#include "cloth_sim/core/collision/surface_topology.h"
#include "cloth_sim/core/linalg/types.h"

namespace cloth_sim {

/// The untangling displacement of one substep.
///
/// Every edge E = (p, q) of one triangle that crosses another triangle T (unit normal N) of the
/// intersecting pairs @p pairs (IntersectionCounter::pairs) is a point X of the intersection
/// contour. Translating E by d relative to T moves X by d - u (N . d) / (N . u) (u = q - p), and
/// the contour leaves X into each face F_i that holds E along R_i = +-(N_Fi x N) (the sign
/// pointing into F_i), so the contour's length changes by -sum_i R_i . dX: its steepest descent
/// moves E relative to T along
///
///   G = sum_i R_i - N (u . sum_i R_i) / (u . N).
///
/// Each crossing adds G / |G| to p and q and subtracts it from T's vertices; each movable
/// particle (@p movable) is then displaced by @p step_length (m) times its sum, the sum's
/// length capped at 1. Returns the number of edge-triangle crossings found; @p displacement
/// (3 x N, m) is overwritten.
int contourDisplacement(const SurfaceTopology& topology, const Points& x,
                        const std::vector<std::pair<int, int>>& pairs,
                        const std::vector<char>& movable, double step_length, Points& displacement);

}  // namespace cloth_sim
