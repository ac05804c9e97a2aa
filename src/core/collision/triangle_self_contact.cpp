#include "cloth_sim/core/collision/triangle_self_contact.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "cloth_sim/core/collision/contour_untangling.h"

namespace cloth_sim {
namespace {

/// The distance a vertex keeps from a triangle is t; an edge keeps kEdgeShare t from another
/// edge: the vertices of two stacked layers then hold them t apart and their edges, listed only
/// within 0.8 t, do not meet (at t for edges too, every edge of a layer was a candidate against
/// a dozen of the other's: 30 to 50 pairs per particle in a two-layer fold at 128 x 128).
constexpr double kEdgeShare = 0.5;
/// Reach of the broad phase (fraction of t): vertex-triangle pairs within 1.25 t and edge pairs
/// within 0.8 t of each other over the substep are listed. The impact stage needs every pair
/// that comes within 0.1 t: so the proximity stage may move a particle (0.8 - 0.1) / 2 = 0.35 t
/// from where the search saw it before a new search is needed.
constexpr double kVertexReach = 1.25, kEdgeReach = 0.8, kMoveCovered = 0.35;
/// The proximity stage runs in one substep of kProximityEvery (and whenever the cloth is
/// tangled); the others run only the impact stage, whose pairs come within 0.1 t: listed within
/// 0.2 t, covered while the pushes move no particle by 0.05 t. Why: at 128 x 128 the pairs
/// within 1.25 t of two resting layers (7 per particle) cost most of a substep, and a layer
/// resting t above another sinks by about g (4 h)^2 / 2 = 0.3 mm in four substeps of 1/480 s.
constexpr int kProximityEvery = 4;
constexpr double kImpactReach = 0.2, kImpactCovered = 0.05;
/// Pairs within this much (fraction of their contact distance) of it at the end of the solve
/// enter the proximity sweeps: pushes during the sweeps rarely close more.
constexpr double kNear = 0.25;
/// Gauss-Seidel sweeps of the proximity stage at most (they stop when no pair is pushed).
constexpr int kSweeps = 6;
constexpr int kScaledRounds = 4;
constexpr int kPushRounds = 3;

PairPoints pairPoints(const PairCandidate& pair, const Points& x) {
  return {x.col(pair.v[0]), x.col(pair.v[1]), x.col(pair.v[2]), x.col(pair.v[3])};
}

}  // namespace

void TriangleContactStats::add(const TriangleContactStats& s) {
  triangle_pairs += s.triangle_pairs;
  candidates += s.candidates;
  proximity += s.proximity;
  corrections += s.corrections;
  impact_tests += s.impact_tests;
  pushed += s.pushed;
  impacts += s.impacts;
  shortened += s.shortened;
  unresolved += s.unresolved;
  tangled_pairs += s.tangled_pairs;
  crossings += s.crossings;
  searches += s.searches;
}

TriangleSelfContact::TriangleSelfContact(const Eigen::Matrix3Xi& triangles, const Points& rest,
                                         double thickness, double friction)
    : topology_(triangles, static_cast<int>(rest.cols())),
      rest_(rest),
      search_(topology_, rest),
      thickness_(thickness),
      friction_(friction),
      counter_(triangles) {
  if (!(thickness > 0.0) || !(friction >= 0.0)) {
    throw std::invalid_argument("self-contact: thickness must be > 0 and friction >= 0");
  }
  // Per substep, the untangling moves a particle at most 0.3 of an edge: a contour leaves a
  // triangle in a few substeps. A tenth of an edge was too slow against the springs that hold a
  // crease: a pin jump's 11 crossing pairs (20 x 20) were still 4 after 4 s.
  untangle_step_ = 0.3 * topology_.meanEdgeLength(rest);
  // Pairs closer than t at rest are no contacts, those closer than 1.25 t touch at 0.8 x their
  // rest distance: when no pair is that close at rest (a thin cloth: t under 0.57 spacings on
  // a square grid), no pair's rest distance need be measured again.
  std::vector<PairCandidate> near;
  search_.find(topology_, rest, rest, 1.25 * thickness, 1.25 * thickness, near, false);
  for (const PairCandidate& pair : near) {
    if (restDistance(pair) < 1.25 * thickness) {
      rest_near_ = true;
      break;
    }
  }
}

double TriangleSelfContact::restDistance(const PairCandidate& pair) const {
  return closestPoints(pair.kind, pairPoints(pair, rest_)).distance;
}

void TriangleSelfContact::findContacts(const CollisionStep& step, const Points& end,
                                       double vertex_reach, double edge_reach) {
  const double t = thickness_;
  search_.find(topology_, step.start, end, vertex_reach, edge_reach, candidates_);
  ++last_.searches;
  last_.triangle_pairs += search_.trianglePairs() + search_.vertexPairs();
  last_.candidates += static_cast<long>(candidates_.size());
  contacts_.resize(candidates_.size());
  skip_.assign(candidates_.size(), 0);
  const bool tangled = !tangled_.empty();
  for (std::size_t i = 0; i < candidates_.size(); ++i) {
    PairContact& c = contacts_[i];
    c.pair = candidates_[i];
    const ClosestPoints cp = closestPoints(c.pair.kind, pairPoints(c.pair, step.start));
    c.weight = cp.weight;
    c.start_distance = cp.distance;
    c.contact_distance = 0.0;
    c.normal.setZero();
    if (cp.distance > 1e-9 * t) {
      Vec3 gap = Vec3::Zero();
      for (int k = 0; k < 4; ++k) gap += c.weight[k] * step.start.col(c.pair.v[k]);
      c.normal = gap / cp.distance;
    }
    if (tangled) {  // both sides in the tangle: free to pass back through each other
      const auto& v = c.pair.v;
      const bool vt = c.pair.kind == PairKind::kVertexTriangle;
      const bool first = tangled_vertex_[v[0]] || (!vt && tangled_vertex_[v[1]]);
      const bool second =
          tangled_vertex_[v[3]] || tangled_vertex_[v[2]] || (vt && tangled_vertex_[v[1]]);
      skip_[i] = first && second;
    }
  }
}

int TriangleSelfContact::resolve(const CollisionStep& step, const GroundPlane& ground, Points& end,
                                 Points& velocities) {
  last_ = TriangleContactStats();
  if (!end.allFinite()) return 0;  // the step's check rolls this frame back
  const Points& start = step.start;
  const int n = static_cast<int>(end.cols());
  const double t = thickness_;

  // 0. Tangles: checked unless this substep continues one proven free of them.
  tangled_.clear();
  if (!verified_ || last_end_.cols() != start.cols() || last_end_ != start) {
    tangled_ = counter_.pairs(start);
  }
  int moved = 0;
  if (!tangled_.empty()) {
    last_.tangled_pairs = static_cast<long>(tangled_.size());
    tangled_vertex_.assign(n, 0);
    const Eigen::Matrix3Xi& tri = topology_.triangles();
    for (const auto& [a, b] : tangled_) {
      for (int k = 0; k < 3; ++k) tangled_vertex_[tri(k, a)] = tangled_vertex_[tri(k, b)] = 1;
    }
    last_.crossings =
        contourDisplacement(topology_, start, tangled_, step.movable, untangle_step_, untangle_);
    end += untangle_;
    moved += static_cast<int>((untangle_.colwise().squaredNorm().array() > 0.0).count());
  }
  before_ = end;
  carry_ = end;

  // 1-2. Broad phase, then proximity for the pairs near contact (in one substep of
  // kProximityEvery: the others list only the pairs the impact stage needs).
  const bool proximity = substep_++ % kProximityEvery == 0 || !tangled_.empty() ||
                         slide_from_.cols() != start.cols();
  if (proximity) slide_from_ = start;
  const double vertex_reach = proximity ? kVertexReach * t : kImpactReach * t;
  const double edge_reach = proximity ? kEdgeReach * t : kImpactReach * t;
  const double covered = proximity ? kMoveCovered : kImpactCovered;
  findContacts(step, end, vertex_reach, edge_reach);
  active_.clear();
  for (std::size_t i = 0; proximity && i < contacts_.size(); ++i) {
    PairContact& c = contacts_[i];
    if (skip_[i] || c.normal.isZero(0.0)) continue;
    const double target = c.pair.kind == PairKind::kVertexTriangle ? t : kEdgeShare * t;
    c.contact_distance = target;
    if (proximityGap(c, end) >= kNear * target) {
      c.contact_distance = 0.0;
      continue;
    }
    if (rest_near_) {
      // Pairs closer than t on the cloth at rest are the springs' business (as in the particle
      // mode); the others get 20 % compression before they touch.
      const double rest = restDistance(c.pair);
      c.contact_distance = rest < t ? 0.0 : std::min(target, 0.8 * rest);
    }
    if (c.contact_distance > 0.0) active_.push_back(static_cast<int>(i));
  }
  last_.proximity = static_cast<long>(active_.size());
  if (!active_.empty()) {
    last_.corrections = projectProximity(contacts_, active_, step, ground, friction_, kSweeps, end,
                                         &carry_, &slide_from_);
  }

  // 3. Impacts: pushed apart where they happen, then the fail-safe. A particle the stages
  // moved more than kMoveCovered t from before_ could meet a pair the search did not list, so
  // the fail-safe then gets a new search.
  const ImpactReport pushed =
      pushImpacts(contacts_, skip_, step, ground, t, kPushRounds, end, &carry_, pushed_);
  const double moved_far = (end - before_).colwise().squaredNorm().maxCoeff();
  if (moved_far > covered * covered * t * t) {
    findContacts(step, end, vertex_reach, edge_reach);
    pushed_.assign(n, 1);  // new contacts: every pair is tested again
  }
  // The first round tests only the pairs pushImpacts did not prove safe over this motion.
  const ImpactReport impacts =
      stopImpacts(contacts_, skip_, step, t, kScaledRounds, end, &carry_, &pushed_);
  last_.impact_tests = pushed.tests + impacts.tests;
  last_.pushed = pushed.hits;
  last_.impacts = impacts.hits;
  last_.shortened = impacts.shortened;
  last_.unresolved = impacts.unresolved;

  for (int i = 0; i < n; ++i) {
    if (end.col(i) == before_.col(i)) continue;
    velocities.col(i) += (carry_.col(i) - before_.col(i)) / step.h;
    ++moved;
  }
  verified_ = tangled_.empty() && impacts.unresolved == 0 && impacts.touching == 0;
  last_end_ = end;
  total_.add(last_);
  return moved;
}

double TriangleSelfContact::minPairDistance(const Points& x, double cap) {
  std::vector<PairCandidate> pairs;
  search_.find(topology_, x, x, cap, cap, pairs);
  double best = cap;
  for (const PairCandidate& p : pairs) {
    if (p.kind != PairKind::kVertexTriangle || restDistance(p) < thickness_) continue;
    best = std::min(best, closestPoints(p.kind, pairPoints(p, x)).distance);
  }
  return best;
}

}  // namespace cloth_sim
