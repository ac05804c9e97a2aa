/// @file impact_failsafe.h
/// The impact stage of triangle self-contact: continuous collision detection of every candidate
/// pair over the substep's motion (start to end, straight lines) and a fail-safe that shortens
/// the motion of the particles involved until no pair comes closer than its minimum distance,
/// so that a cloth free of intersections at the start of a substep is free of them at its end
/// (docs/method.md, "Self-contact").
#pragma once

#include <vector>

#include "cloth_sim/core/collision/additive_ccd.h"
#include "cloth_sim/core/collision/colliders.h"
#include "cloth_sim/core/collision/proximity_projection.h"
#include "cloth_sim/core/linalg/types.h"

namespace cloth_sim {

/// What stopImpacts did.
struct ImpactReport {
  int tests = 0;        ///< pairs run through additive CCD (the others were cleared at once)
  int hits = 0;         ///< pair impacts found, summed over the rounds
  int rounds = 0;       ///< rounds of detection that found impacts
  int shortened = 0;    ///< particles whose motion was shortened (or stopped)
  /// Pairs still colliding at the end: only possible when the motion that collides belongs to
  /// hard-pinned particles, which the fail-safe cannot stop. 0 guarantees the substep crossed
  /// nothing.
  int unresolved = 0;
  /// Pairs touching at the start (closer than 4e-9 t): no side to keep, so not tested; the
  /// caller must check the end for intersections.
  int touching = 0;
};

/// Minimum distance (m) the impact stage keeps for a pair @p start_distance apart at the start
/// of the substep, for a cloth of thickness @p thickness: 0.1 t, or a quarter of the start
/// distance for a pair closer than 0.4 t (never below what it starts at, so a pair that does not
/// move relative to itself is never an impact).
inline double impactDistance(double thickness, double start_distance) {
  return std::min(0.1 * thickness, 0.25 * start_distance);
}

/// The impact response before the fail-safe (Bridson, Fedkiw and Anderson 2002, section 7.2,
/// as position corrections): each pair of @p contacts (those with @p skip[i] false) whose
/// motion from @p step.start to @p end comes closer than impactDistance (additive CCD) is
/// pushed apart at the end to half the thickness along the direction between its closest
/// points at the time of impact (pushApart: linear momentum kept, the ground holding what lies
/// on it); the next of @p rounds tests the pairs whose particles moved. The pushes keep the
/// motion a collision leaves (the slide along the contact) where the fail-safe would stop it,
/// and put the pair back at a distance from which the next substep's impact distance does not
/// shrink. Pushed particles may leave the broad phase's boxes: the caller searches again when
/// they moved far. @p carry as in pushApart; @p moved gets 1 for each particle of a pair found
/// colliding (pushed or not). The CCD tests run on @p threads (the pushes in pair order: the
/// same result on any number). Returns the report (hits and tests; nothing is shortened).
ImpactReport pushImpacts(const std::vector<PairContact>& contacts, const std::vector<char>& skip,
                         const CollisionStep& step, const GroundPlane& ground, double thickness,
                         int rounds, Points& end, Points* carry, std::vector<char>& moved,
                         int threads = 1);

/// Detects the impacts of @p contacts (those with @p skip[i] false) over the motion from
/// @p step.start to @p end by additive CCD (additive_ccd.h) down to impactDistance, and removes
/// them. Each round, every pair that collides shortens the motion of its movable particles to
/// the time it is proven safe (x_start + s (x_end - x_start), s the pair's safe time: its own
/// motion becomes a prefix of the colliding one); the next round tests again the pairs whose
/// particles changed. After @p scaled_rounds rounds, colliding pairs stop their movable
/// particles outright (s = 0); the stopped set only grows, so the rounds end. Motions stay on the
/// straight paths the broad phase bounded, so no new candidate can appear. Each change of an
/// end position is made to @p carry too (if given; see pushApart). With @p moved, the first
/// round tests only the pairs with a particle marked there (the others were found safe over
/// this motion already, by pushImpacts). The CCD tests run on @p threads (the same result on
/// any number).
ImpactReport stopImpacts(const std::vector<PairContact>& contacts, const std::vector<char>& skip,
                         const CollisionStep& step, double thickness, int scaled_rounds,
                         Points& end, Points* carry, const std::vector<char>* moved = nullptr,
                         int threads = 1);

}  // namespace cloth_sim
