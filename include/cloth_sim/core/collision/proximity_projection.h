/// @file proximity_projection.h
/// The proximity stage of triangle self-contact: vertex-triangle and edge-edge pairs closer than
/// their contact distance are pushed apart after the solve, with Coulomb friction (Bridson,
/// Fedkiw and Anderson 2002, "Robust treatment of collisions, contact and friction for cloth
/// animation", section 7.1, as position corrections; docs/method.md, "Self-contact").
#pragma once

#include <array>
#include <vector>

#include "cloth_sim/core/collision/colliders.h"
#include "cloth_sim/core/collision/pair_search.h"
#include "cloth_sim/core/linalg/types.h"

namespace cloth_sim {

/// A candidate pair with its closest points at the start of the substep.
struct PairContact {
  PairCandidate pair;
  /// Weights of the closest points at the start (ClosestPoints::weight): the gap vector is
  /// sum_k weight[k] x_{v[k]}. Kept for the substep, as the normal.
  std::array<double, 4> weight{};
  /// Unit vector from the second primitive's closest point to the first's at the start; zero
  /// when they touched there (no side to push to: left to the impact stage).
  Vec3 normal = Vec3::Zero();
  double start_distance = 0.0;  ///< m, at the start of the substep
  /// Distance (m) the proximity stage keeps along the normal; 0 = not a proximity contact (the
  /// pair is closer than the thickness on the cloth at rest, or tangled).
  double contact_distance = 0.0;
};

/// Gap (m) of contact @p c at positions @p x along its normal, minus its contact distance:
/// negative when the pair is too close (or on the wrong side).
inline double proximityGap(const PairContact& c, const Points& x) {
  Vec3 g = Vec3::Zero();
  for (int k = 0; k < 4; ++k) g += c.weight[k] * x.col(c.pair.v[k]);
  return c.normal.dot(g) - c.contact_distance;
}

/// Pushes apart the contacts of @p contacts listed in @p active (indices), @p sweeps Gauss-Seidel
/// sweeps: a contact with negative gap moves its four vertices along its normal, each by its
/// weight times its inverse mass (hard-pinned particles do not move), so the gap closes and the
/// linear momentum stays; then Coulomb friction cuts the two closest points' relative slide
/// over the substep by @p mu times that push (applyFriction). A particle lying on @p ground (if
/// enabled) is not pushed down into it: the other side of the contact moves instead. After each
/// sweep the ground clamps the movable particles onto it (the ground keeps the last word, as
/// for the particle mode). Returns the number of contact corrections made.
int projectProximity(const std::vector<PairContact>& contacts, const std::vector<int>& active,
                     const CollisionStep& step, const GroundPlane& ground, double mu, int sweeps,
                     Points& end);

}  // namespace cloth_sim
