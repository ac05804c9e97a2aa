/// @file triangle_self_contact.h
/// Self-contact of a cloth between its triangles and edges, at any thickness: proximity
/// (vertex-triangle and edge-edge pairs pushed to the thickness, with friction), continuous
/// detection of every impact over the substep with a fail-safe that stops it, and the untangling
/// of a cloth that already passes through itself (docs/method.md, "Self-contact").
#pragma once

#include <utility>
#include <vector>

#include "cloth_sim/core/collision/colliders.h"
#include "cloth_sim/core/collision/contact_forces.h"
#include "cloth_sim/core/collision/impact_failsafe.h"
#include "cloth_sim/core/collision/pair_list.h"
#include "cloth_sim/core/collision/pair_search.h"
#include "cloth_sim/core/collision/proximity_projection.h"
#include "cloth_sim/core/collision/surface_topology.h"
#include "cloth_sim/core/collision/triangle_intersection.h"
#include "cloth_sim/core/linalg/types.h"

namespace cloth_sim {

/// What one substep of TriangleSelfContact did (or, summed, a run).
struct TriangleContactStats {
  long triangle_pairs = 0;  ///< pairs of triangles whose boxes overlap in the broad phase
  long candidates = 0;    ///< vertex-triangle and edge-edge pairs from the broad phase
  long proximity = 0;     ///< pairs near contact, given to the proximity stage
  long corrections = 0;   ///< proximity corrections made (over the sweeps)
  long impact_tests = 0;  ///< pairs run through additive CCD
  long pushed = 0;        ///< impacts pushed apart (summed over the rounds)
  long impacts = 0;       ///< impacts the fail-safe found and stopped
  long shortened = 0;     ///< particles whose motion the fail-safe shortened
  long unresolved = 0;    ///< impacts left (pinned motion): the cloth may cross itself
  long tangled_pairs = 0; ///< intersecting triangle pairs at the start of the substep
  long crossings = 0;     ///< edge-triangle crossings the untangling moved
  long searches = 0;      ///< broad-phase runs (1 per substep, 2 when the proximity moved far)
  long listed = 0;        ///< of those, the ones the pair list served (no search of the paths)
  void add(const TriangleContactStats& s);
};

/// Triangle self-contact (Bridson, Fedkiw and Anderson 2002, "Robust treatment of collisions,
/// contact and friction for cloth animation", with additive CCD from Li, Kaufman and Jiang 2021,
/// "Codimensional Incremental Potential Contact", and intersection contour minimization from
/// Volino and Magnenat-Thalmann 2006), run after the solve and the colliders in each substep:
///
/// 0. Untangling: unless the substep starts where the last one ended with its result proven
///    free of intersections, the start is checked (IntersectionCounter); intersecting triangles
///    get the contour minimization displacement (contour_untangling.h) and pairs between their
///    vertices are left out of the stages below, which would otherwise hold the crossing.
/// 1. Broad phase (PairSearch): vertex-triangle pairs whose swept boxes come within 1.25 t,
///    edge pairs within 0.8 t; while the cloth moves less than kListMargin t a substep, from a
///    list kept between substeps (PairList) instead of a search of the paths.
/// 2. Proximity (projectProximity): each pair's closest points and normal at the start; a pair
///    near contact at the end and at least t apart on the cloth at rest is kept
///    d = min(t, 0.8 x its rest distance) apart along that normal, with Coulomb friction; at
///    most six Gauss-Seidel sweeps, the ground clamped after each.
/// 3. Impacts: additive CCD of every pair over start -> end down to impactDistance; each impact
///    pushed apart at its time of impact (pushImpacts, 3 rounds), then the fail-safe that
///    shortens colliding motions (stopImpacts, 4 scaled rounds, then stops). A substep that starts free of intersections ends free of them, unless a
///    hard-pinned particle is driven through the cloth (then the next substep untangles).
/// 4. The proximity pairs still within 1.5 d at the end, linearised there (solvePairs), go
///    into the next substep's solve as contact forces (ContactForces::SelfPair).
///
/// Velocities get the change of position of stages 2 and 3 over h, except the part of a push
/// that restores the thickness of a pair already too close (pushApart): that one, and the
/// untangling, move positions only, adding no energy.
class TriangleSelfContact {
 public:
  /// @p triangles: the cloth's triangles; @p rest: rest positions (m); @p thickness: t (m, > 0);
  /// @p friction: Coulomb mu (>= 0).
  TriangleSelfContact(const Eigen::Matrix3Xi& triangles, const Points& rest, double thickness,
                      double friction);

  double thickness() const { return thickness_; }
  /// See the class. Returns the particles moved (untangling included).
  int resolve(const CollisionStep& step, const GroundPlane& ground, Points& end,
              Points& velocities);

  const TriangleContactStats& lastStats() const { return last_; }
  /// The proximity pairs of the last resolve still within 1.5 times their contact distance at
  /// its end, linearised there: the next step's solve keeps them apart (the substep pipeline
  /// swaps them into ContactForces::swapSelfPairs).
  std::vector<ContactForces::SelfPair>& solvePairs() { return solve_pairs_; }
  const TriangleContactStats& totalStats() const { return total_; }
  const SurfaceTopology& topology() const { return topology_; }
  /// Smallest distance (m) between a vertex and a triangle sharing no vertex and at least t
  /// apart at rest, among the pairs within @p cap (m) at @p x; @p cap if none (for tests: the
  /// layers' separation).
  double minPairDistance(const Points& x, double cap);
  /// Threads of the intersection check of a substep's start (IntersectionCounter::setThreads),
  /// of the broad phase's walk (PairSearch::setThreads) and of the pairs' start geometry; the
  /// other stages run on one. The result is the same on any number.
  void setThreads(int threads) {
    threads_ = threads;
    counter_.setThreads(threads);
    search_.setThreads(threads);
    list_.setThreads(threads);
  }

 private:
  /// contacts_ from the broad phase's pairs for the motion start -> end.
  void findContacts(const CollisionStep& step, const Points& end, double vertex_reach,
                    double edge_reach);
  /// Contact @p index of contacts_ (and skip_) from candidates_[index] with its start geometry.
  void setContact(const CollisionStep& step, std::size_t index);
  /// solve_pairs_ from the proximity pairs (active_) at the resolve's @p end.
  void listSolvePairs(const Points& end);
  /// The pair's distance on the cloth at rest (m).
  double restDistance(const PairCandidate& pair) const;

  SurfaceTopology topology_;
  Points rest_;
  PairSearch search_;
  PairList list_;
  double thickness_ = 0.0, friction_ = 0.0, untangle_step_ = 0.0;
  IntersectionCounter counter_;
  std::vector<PairCandidate> candidates_;
  std::vector<PairContact> contacts_;
  std::vector<int> active_;
  std::vector<ContactForces::SelfPair> solve_pairs_;
  std::vector<ContactForces::SelfPair> listed_;  ///< listSolvePairs' work buffers
  std::vector<char> keep_;
  std::vector<char> skip_, tangled_vertex_, pushed_;
  std::vector<std::pair<int, int>> tangled_;
  Points last_end_, before_, carry_, untangle_;
  int threads_ = 1;
  bool verified_ = false;  ///< last_end_ is proven free of intersections
  bool rest_near_ = false; ///< some pair is closer than 1.25 t at rest (rest distances matter)
  TriangleContactStats last_, total_;
};

}  // namespace cloth_sim
