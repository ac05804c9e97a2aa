/// @file contact_projection.h
/// Small pieces of the position-level contact response shared by every collider type.
#pragma once

#include <optional>

#include <Eigen/Geometry>

#include "cloth_sim/core/linalg/types.h"

namespace cloth_sim {

/// Coulomb friction on a contact displacement (Liu et al. 2013 style position response):
/// removes up to mu * normal_correction (m) of the part of @p displacement tangent to @p normal,
/// and all of it when that part is smaller (static friction: the particle sticks).
Vec3 applyFriction(const Vec3& displacement, const Vec3& normal, double normal_correction,
                   double mu);

/// Normal correction (m) that friction may press with at a contact of normal @p normal: the
/// part of @p correction that the particle's free motion @p free_motion (h v + h^2 g relative
/// to the collider: inertia and weight) drove into the surface, or all of it without one.
///
/// Why: in a position projection the correction also contains what the springs pulled the
/// particle into the collider. On a box's top edge a particle on the side face, pulled inwards
/// by its neighbour on the top, was then held by that pull's own friction and the spring
/// between them stayed stretched 50-200 % (the real normal force acts on the edge, which
/// carries the spring, not on the particle); likewise round a small ball on the ground. Weight
/// and impacts keep their full Coulomb friction (a cloth at rest on a slope stays; a resting
/// particle's load is its weight, m g h^2 of correction per step).
double frictionLoad(double correction, const Vec3& normal, const std::optional<Vec3>& free_motion);

/// Closest point to @p p on triangle (a, b, c) (Ericson, Real-Time Collision Detection 5.1.5).
Vec3 closestPointOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

/// First parameter t in [0, 1] where the path start + t path enters the sphere of radius
/// @p radius centred at the origin (the smaller root of |start + t path|^2 = r^2), or a
/// negative value if it does not (a start inside the sphere has no entry).
double sphereEntry(const Vec3& start, const Vec3& path, double radius);

/// Parameter t in [0, 1] where segment p + t (q - p) crosses triangle (a, b, c), or a negative
/// value if it does not (Moller-Trumbore; a segment lying in the triangle's plane is a miss).
double segmentTriangleCrossing(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b,
                               const Vec3& c);

}  // namespace cloth_sim
