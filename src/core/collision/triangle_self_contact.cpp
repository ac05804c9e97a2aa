#include "cloth_sim/core/collision/triangle_self_contact.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "cloth_sim/core/collision/contour_untangling.h"
#include "cloth_sim/core/linalg/parallel.h"

namespace cloth_sim {
namespace {

/// The distance an edge keeps from another edge, as a fraction of t (a vertex keeps t from a
/// triangle). At 0.5 (so that two layers stacked t apart list no edge pair) the pile scene
/// ended with a vertex 0.1 t from another layer and particles moving at 2.4 m/s (measured, with
/// kNear 0.25; 0.24 t and 1.2 m/s with kNear 0.5); at 1 it keeps t.
constexpr double kEdgeShare = 1.0;
/// Reach of the broad phase (fraction of t): vertex-triangle pairs within 1.25 t and edge pairs
/// within 0.8 t of each other over the substep are listed (so edges closer than t but not 0.8 t
/// are left alone; once within 0.8 t they are pushed back to t). The impact stage needs every pair
/// that comes within 0.1 t: so the proximity stage may move a particle (0.8 - 0.1) / 2 = 0.35 t
/// from where the search saw it before a new search is needed.
constexpr double kVertexReach = 1.25, kEdgeReach = 0.8, kMoveCovered = 0.35;
/// The pair list's margin (fraction of t): it serves while every vertex stays within this of
/// its anchor, and lists the pairs within their reach plus twice this at the anchors.
constexpr double kListMargin = 0.1;
/// Pairs within this much (fraction of their contact distance) of it at the end of the solve
/// enter the proximity sweeps: pushes during the sweeps rarely close more. At 0.25 the pin
/// jump of TangleRecovery kept its crease (max strain 0.57 at the end against 0.07 at 0.5,
/// measured).
constexpr double kNear = 0.5;
/// Gauss-Seidel sweeps of the proximity stage at most (they stop when no pair is pushed).
constexpr int kSweeps = 6;
constexpr int kScaledRounds = 4;
constexpr int kPushRounds = 3;
/// Pairs per block of the start geometry computed on threads.
constexpr std::size_t kContactGrain = 2048;

PairPoints pairPoints(const PairCandidate& pair, const Points& x) {
  return {x.col(pair.v[0]), x.col(pair.v[1]), x.col(pair.v[2]), x.col(pair.v[3])};
}

/// Unit vector from the second primitive's closest point to the first's at @p x (@p cp there);
/// zero when they are within @p touching of each other (no side to push to).
Vec3 pairNormal(const PairCandidate& pair, const ClosestPoints& cp, const Points& x,
                double touching) {
  if (!(cp.distance > touching)) return Vec3::Zero();
  Vec3 gap = Vec3::Zero();
  for (int k = 0; k < 4; ++k) gap += cp.weight[k] * x.col(pair.v[k]);
  return gap / cp.distance;
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
  listed += s.listed;
}

TriangleSelfContact::TriangleSelfContact(const Eigen::Matrix3Xi& triangles, const Points& rest,
                                         double thickness, double friction)
    : topology_(triangles, static_cast<int>(rest.cols())),
      rest_(rest),
      search_(topology_, rest),
      list_(search_, kListMargin * (thickness > 0.0 ? thickness : 1.0)),
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
  ++last_.searches;
  // Where pairs are near at rest (a thick cloth), the list would hold every neighbour.
  if (!rest_near_ &&
      list_.find(search_, topology_, step.start, end, vertex_reach, edge_reach, candidates_)) {
    ++last_.listed;
  } else {
    if (rest_near_) search_.find(topology_, step.start, end, vertex_reach, edge_reach, candidates_);
    last_.triangle_pairs += search_.trianglePairs() + search_.vertexPairs();
  }
  contacts_.resize(candidates_.size());
  skip_.resize(candidates_.size());
  const BlockSplit split(candidates_.size(), kContactGrain);
  parallelFor(threads_, split.blocks(), [&](int b) {
    for (std::size_t i = split.begin(b); i < split.end(b); ++i) setContact(step, i);
  });
  last_.candidates += static_cast<long>(candidates_.size());
}

void TriangleSelfContact::setContact(const CollisionStep& step, std::size_t index) {
  const double t = thickness_;
  PairContact c;
  c.pair = candidates_[index];
  const ClosestPoints cp = closestPoints(c.pair.kind, pairPoints(c.pair, step.start));
  c.weight = cp.weight;
  c.start_distance = cp.distance;
  c.normal = pairNormal(c.pair, cp, step.start, 1e-9 * t);
  char skip = 0;
  if (!tangled_.empty()) {  // both sides in the tangle: free to pass back through each other
    const auto& v = c.pair.v;
    const bool vt = c.pair.kind == PairKind::kVertexTriangle;
    const bool first = tangled_vertex_[v[0]] || (!vt && tangled_vertex_[v[1]]);
    const bool second =
        tangled_vertex_[v[3]] || tangled_vertex_[v[2]] || (vt && tangled_vertex_[v[1]]);
    skip = first && second;
  }
  contacts_[index] = c;
  skip_[index] = skip;
}

int TriangleSelfContact::resolve(const CollisionStep& step, const GroundPlane& ground, Points& end,
                                 Points& velocities) {
  last_ = TriangleContactStats();
  solve_pairs_.clear();
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

  // 1-2. Broad phase, then proximity for the pairs near contact.
  findContacts(step, end, kVertexReach * t, kEdgeReach * t);
  active_.clear();
  for (std::size_t i = 0; i < contacts_.size(); ++i) {
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
    last_.corrections =
        projectProximity(contacts_, active_, step, ground, friction_, kSweeps, end, &carry_);
  }

  // 3. Impacts: pushed apart where they happen, then the fail-safe. The pairs in hand cover
  // every pair that comes within 0.1 t while no particle has moved kMoveCovered t from where
  // the search saw it (before_); past that, a new search.
  const ImpactReport pushed =
      pushImpacts(contacts_, skip_, step, ground, t, kPushRounds, end, &carry_, pushed_, threads_);
  const double moved_far = (end - before_).colwise().squaredNorm().maxCoeff();
  if (moved_far >= kMoveCovered * kMoveCovered * t * t) {
    findContacts(step, end, kVertexReach * t, kEdgeReach * t);
    pushed_.assign(n, 1);  // new contacts: every pair is tested again
  }
  // The first round tests only the pairs pushImpacts did not prove safe over this motion.
  const ImpactReport impacts =
      stopImpacts(contacts_, skip_, step, t, kScaledRounds, end, &carry_, &pushed_, threads_);
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
  listSolvePairs(end);
  verified_ = tangled_.empty() && impacts.unresolved == 0 && impacts.touching == 0;
  last_end_ = end;
  total_.add(last_);
  return moved;
}

void TriangleSelfContact::listSolvePairs(const Points& end) {
  // The proximity pairs still within the stage's reach at the end, linearised there (where the
  // next step starts); a pair the end sees from the other side is left to the impact stage.
  // Each pair in fixed blocks, then the kept ones in pair order: the same list on any threads.
  listed_.resize(active_.size());
  keep_.assign(active_.size(), 0);
  const BlockSplit split(active_.size(), kContactGrain);
  parallelFor(threads_, split.blocks(), [&](int b) {
    for (std::size_t i = split.begin(b); i < split.end(b); ++i) {
      const PairContact& c = contacts_[active_[i]];
      const ClosestPoints cp = closestPoints(c.pair.kind, pairPoints(c.pair, end));
      if (cp.distance >= (1.0 + kNear) * c.contact_distance) continue;
      const Vec3 normal = pairNormal(c.pair, cp, end, 1e-9 * thickness_);
      if (!(normal.dot(c.normal) > 0.0)) continue;  // touching, or seen from the other side
      ContactForces::SelfPair& p = listed_[i];
      p.vertex = c.pair.v;
      p.weight = cp.weight;
      p.normal = normal;
      p.distance = c.contact_distance;
      p.mu = friction_;
      p.edges = c.pair.kind == PairKind::kEdgeEdge;
      keep_[i] = 1;
    }
  });
  for (std::size_t i = 0; i < listed_.size(); ++i) {
    if (keep_[i]) solve_pairs_.push_back(listed_[i]);
  }
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
