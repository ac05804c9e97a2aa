/// @file particle_self_contact.h
/// Self-contact mode `particles`: particles that are not mesh neighbours keep at least a
/// thickness apart, which needs a thickness of about the particle spacing (docs/method.md,
/// "Self-contact", "The particle mode"). The cheap mode, kept for comparison with the triangle
/// mode (triangle_self_contact.h).
#pragma once

#include <utility>
#include <vector>

#include <Eigen/Core>

#include "cloth_sim/core/collision/cell_hash.h"
#include "cloth_sim/core/collision/colliders.h"
#include "cloth_sim/core/linalg/parallel.h"
#include "cloth_sim/core/linalg/types.h"

namespace cloth_sim {

/// Particle-particle self-contact by projection (Muller et al. 2007 "Position based dynamics",
/// with the thickness of Macklin et al. 2014 "Unified particle physics", section 7.1), run after
/// the solve and the collider projection of every substep:
///
/// 1. limitDisplacement: no movable particle moves more than 0.3 t in a substep, so two
///    particles approach by at most 0.6 t, less than the 0.71 t gap that a layer leaves between
///    itself and another resting on it when t >= s; a particle cannot cross a layer between two
///    substeps unseen (the bound, instead of continuous detection).
/// 2. resolve: the candidate pairs are found with a CellHash (a Verlet list: rebuilt when a
///    particle has moved 0.2 t since the last build, pairs within d + 0.5 t); each pair closer
///    than its contact distance and not sharing a triangle is pushed apart along the
///    line between them, shared by inverse mass (hard-pinned particles do not move), with
///    Coulomb friction on their relative slide over the substep; four Gauss-Seidel sweeps, each
///    followed by the ground clamp (the ground stays the last word). A pair closer than t at
///    rest is never a contact (its springs keep it apart); the others touch at
///    d = min(t, 0.8 rest distance), so a compressed cloth does not push itself apart.
///
/// Velocities get the change of position over h, so they stay consistent with the positions.
class ParticleSelfContact {
 public:
  /// The thinnest t (m) this mode keeps a cloth from crossing itself: 1.05 x the widest hole of
  /// the rest triangles (the point of a triangle farthest from its corners: the circumcentre of
  /// an acute triangle, the midpoint of the longest side of an obtuse one; s / sqrt 2 on a
  /// square grid of spacing s). Why: a particle resting on a layer sits sqrt(t^2 - R^2) above
  /// its hole of radius R, and the bound lets two particles approach by 0.6 t per substep, so
  /// crossing unseen needs 2 sqrt(t^2 - R^2) <= 0.6 t, i.e. R >= 0.954 t.
  static double minimumThickness(const Eigen::Matrix3Xi& triangles, const Points& rest);

  /// @p triangles: the cloth's triangles (mesh neighbours are never in contact); @p rest: rest
  /// positions (m), which give the rest distance of each pair; @p thickness: t (m, > 0);
  /// @p friction: Coulomb mu (>= 0). Throws std::invalid_argument for a vertex out of range.
  ParticleSelfContact(const Eigen::Matrix3Xi& triangles, const Points& rest, double thickness,
                      double friction);

  /// The contact distance t in use (m).
  double thickness() const { return thickness_; }
  double friction() const { return friction_; }
  /// Largest displacement (m) of a particle in one substep: 0.3 t.
  double maxDisplacement() const { return 0.3 * thickness_; }

  /// Shortens the displacement end - start of every movable particle to maxDisplacement();
  /// velocities change by the change of position over h. Returns the particles shortened.
  int limitDisplacement(const CollisionStep& step, Points& end, Points& velocities) const;

  /// Pushes apart the particles in contact (see the class); @p ground is clamped after each
  /// sweep when enabled. Returns the particles moved.
  int resolve(const CollisionStep& step, const GroundPlane& ground, Points& end,
              Points& velocities);

  /// The pairs (i < j) of non-neighbour particles closer than their contact distance at
  /// @p positions (for tests; the same search as resolve).
  std::vector<std::pair<int, int>> contacts(const Points& positions);
  /// How many times resolve has rebuilt its pair list (for tests and the benchmark).
  long rebuilds() const { return rebuilds_; }
  /// Threads of the pair search (fixed blocks of particles: the same pairs, in the same order,
  /// for any count).
  void setThreads(int threads) { threads_ = threads; }

 private:
  bool neighbours(int i, int j) const;
  /// Fills pairs_ with the candidate pairs within their contact distance plus @p margin.
  void findPairs(const Points& x, double margin);

  double thickness_ = 0.0;
  double friction_ = 0.0;
  Points rest_;
  std::vector<int> ring_start_, ring_;  ///< CSR: the sorted 1-ring of each particle
  CellHash hash_;
  struct Pair {
    int i, j;
    double distance;  ///< contact distance d (m)
  };
  std::vector<Pair> pairs_;
  std::vector<Pair> active_;  ///< the pairs near contact in this substep
  Points built_at_;           ///< positions pairs_ was built at (empty: none)
  long rebuilds_ = 0;
  Points before_;
  int threads_ = 1;
};

}  // namespace cloth_sim
