/// @file sphere_impacts.h
/// Rigid-body impacts of the spheres: with each other and with the ground.
#pragma once

#include "cloth_sim/core/collision/colliders.h"

namespace cloth_sim {

/// Resolves sphere-sphere and dynamic-sphere-ground contacts after a step (sequential impulses,
/// a few sweeps so stacks settle):
///  - overlaps are removed by moving the spheres apart in proportion to their inverse masses
///    (a kinematic sphere has none and does not move), without touching velocities, so the
///    projection adds no energy;
///  - an approaching contact gets a normal impulse leaving a relative normal speed e times the
///    incoming one, e the larger restitution of the two (the sphere's own against the ground),
///    so a bouncy ball bounces off a still kinematic sphere;
///    impacts slower than @p resting_speed (m/s) do not bounce, so a ball resting under gravity
///    stays at rest (Simulation passes 2 |g| h, the speed gravity adds in two steps);
///  - then a Coulomb friction impulse at the contact point, on the slip velocity including spin,
///    at most mu times the normal impulse, mu the larger friction of the two (the ground's
///    against the ground). A ball sliding on the ground thus ends rolling at 5/7 of its speed.
/// Linear momentum is conserved in sphere-sphere impacts between dynamic spheres. Returns the
/// number of contacts found in the first sweep.
int resolveSphereImpacts(Colliders& colliders, double resting_speed);

}  // namespace cloth_sim
