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

/// Closes the negative gap @p gap (m) of the constraint n . sum_k weight[k] x_{v[k]} >= d of the
/// four particles @p v: each moves along @p normal by its weight times its inverse mass (hard
/// pins and, for a push down, particles lying on @p ground do not move), so sum_k m_k dx_k = 0;
/// then Coulomb friction cuts their closest points' relative slide over the substep by @p mu
/// times the push (in @p carry too). Returns false when no particle can move.
///
/// @p carry (if given) holds the positions the velocities will follow, (carry - start) / h: it
/// gets only the part of the push that stops the pair's approach over the substep (an inelastic
/// impact; Bridson et al. 2002, section 7.1, limit their repulsion impulses likewise), and the
/// friction. The rest, which restores the thickness of a pair that was already too close, moves
/// positions only: as velocity it threw pressed layers apart and a pile gained energy until it
/// blew up (0.13 J to 19 J in 1.3 s, measured).
bool pushApart(const std::array<int, 4>& v, const std::array<double, 4>& weight,
               const Vec3& normal, double gap, const CollisionStep& step,
               const GroundPlane& ground, double mu, Points& end, Points* carry);

/// Pushes apart the contacts of @p contacts listed in @p active (indices) by Gauss-Seidel
/// sweeps (pushApart for each pair with a negative gap beyond 0.1 % of its contact distance),
/// at most @p sweeps of them, stopping after a sweep that pushed nothing. After each sweep
/// @p ground, if enabled, clamps the movable particles of the contacts onto it (the ground
/// keeps the last word, as for the particle mode). @p mu, @p carry as in pushApart (@p carry is
/// clamped too). Returns the number of pushes made.
int projectProximity(const std::vector<PairContact>& contacts, const std::vector<int>& active,
                     const CollisionStep& step, const GroundPlane& ground, double mu, int sweeps,
                     Points& end, Points* carry);

}  // namespace cloth_sim
