#include "cloth_sim/core/collision/impact_failsafe.h"

#include <algorithm>

#include "cloth_sim/core/collision/additive_ccd.h"
#include "cloth_sim/core/linalg/parallel.h"

namespace cloth_sim {
namespace {

/// Safe time of contact @p c over the motion start -> end; 1 when it cannot collide.
CcdResult safeTime(const PairContact& c, const Points& start, const Points& end,
                   double thickness, int& tests) {
  const double min_distance = impactDistance(thickness, c.start_distance);
  // Touching at the start (to rounding): no side to keep, nothing to stop. stopImpacts counts
  // it, and the caller checks the end for intersections (the untangling answers for them).
  if (!(min_distance > 1e-9 * thickness)) return CcdResult{};
  PairPoints x0, motion;
  double side[2] = {0.0, 0.0};  // the largest motion on each side, for a first cheap test
  for (int k = 0; k < 4; ++k) {
    const int v = c.pair.v[k];
    x0[k] = start.col(v);
    motion[k] = end.col(v) - start.col(v);
    const int s = (c.pair.kind == PairKind::kVertexTriangle ? k >= 1 : k >= 2) ? 1 : 0;
    side[s] = std::max(side[s], motion[k].norm());
  }
  // Without removing the common motion: the gap closes by at most the two sides' motions.
  if (c.start_distance - min_distance > side[0] + side[1]) return CcdResult{};
  ++tests;
  return additiveCcd(c.pair.kind, x0, motion, min_distance);
}

/// Pairs per block of the CCD tests run on threads.
constexpr std::size_t kCcdGrain = 1024;

/// Runs additive CCD on each pair of @p contacts that is not skipped and has a particle marked in
/// @p changed, over the motion start -> @p end, and calls @p on_hit(pair, its CCD result) for
/// each that collides, in pair order. Returns the number of those (a round's hits).
/// The tests run first, in fixed blocks on @p threads, on the end as it is; a hit that moves
/// particles marks them in @p dirty (if given), and a later pair with a dirty particle is tested
/// again on the end as it then is: the same hits and results as testing each pair in turn.
template <typename OnHit>
int forEachImpact(const std::vector<PairContact>& contacts, const std::vector<char>& skip,
                  const std::vector<char>& changed, const Points& start, const Points& end,
                  double thickness, int threads, std::vector<char>* dirty,
                  std::vector<CcdResult>& results, int& tests, OnHit&& on_hit) {
  const auto tested = [&](std::size_t i) {
    const auto& v = contacts[i].pair.v;
    return !skip[i] && (changed[v[0]] || changed[v[1]] || changed[v[2]] || changed[v[3]]);
  };
  const BlockSplit split(contacts.size(), kCcdGrain);
  std::vector<int> block_tests(static_cast<std::size_t>(split.blocks()), 0);
  results.resize(contacts.size());
  parallelFor(threads, split.blocks(), [&](int b) {
    for (std::size_t i = split.begin(b); i < split.end(b); ++i) {
      results[i] = tested(i) ? safeTime(contacts[i], start, end, thickness, block_tests[b])
                             : CcdResult{};
    }
  });
  for (const int t : block_tests) tests += t;
  if (dirty != nullptr) std::fill(dirty->begin(), dirty->end(), 0);
  int hits = 0;
  for (std::size_t i = 0; i < contacts.size(); ++i) {
    if (!tested(i)) continue;
    const PairContact& c = contacts[i];
    const auto& v = c.pair.v;
    CcdResult ccd = results[i];
    if (dirty != nullptr && ((*dirty)[v[0]] || (*dirty)[v[1]] || (*dirty)[v[2]] || (*dirty)[v[3]])) {
      ccd = safeTime(c, start, end, thickness, tests);
    }
    if (ccd.safe_time >= 1.0) continue;
    ++hits;
    on_hit(c, ccd);
  }
  return hits;
}

}  // namespace

ImpactReport pushImpacts(const std::vector<PairContact>& contacts, const std::vector<char>& skip,
                         const CollisionStep& step, const GroundPlane& ground, double thickness,
                         int rounds, Points& end, Points* carry, std::vector<char>& moved,
                         int threads) {
  ImpactReport report;
  const Points& start = step.start;
  const int n = static_cast<int>(end.cols());
  std::vector<char> changed(n, 1), next_changed(n, 0), dirty(n, 0);
  std::vector<CcdResult> results;
  moved.assign(n, 0);
  for (int round = 0; round < rounds; ++round) {
    std::fill(next_changed.begin(), next_changed.end(), 0);
    const int hits = forEachImpact(contacts, skip, changed, start, end, thickness, threads, &dirty,
                                   results, report.tests,
                                   [&](const PairContact& c, const CcdResult& ccd) {
      const auto& v = c.pair.v;
      for (int k = 0; k < 4; ++k) moved[v[k]] = 1;  // stopImpacts tests it again
      // The closest points where the pair stops: their direction is the side to keep.
      PairPoints at;
      for (int k = 0; k < 4; ++k) {
        at[k] = start.col(v[k]) + ccd.safe_time * (end.col(v[k]) - start.col(v[k]));
      }
      const ClosestPoints cp = closestPoints(c.pair.kind, at);
      if (!(cp.distance > 0.0)) return;
      const Vec3 normal = gapVector(cp, at[0], at[1], at[2], at[3]) / cp.distance;
      Vec3 g = Vec3::Zero();
      for (int k = 0; k < 4; ++k) g += cp.weight[k] * end.col(v[k]);
      const double gap = normal.dot(g) - 0.5 * thickness;
      if (gap >= 0.0) return;  // apart at the end: it went round; the fail-safe decides
      if (pushApart(v, cp.weight, normal, gap, step, ground, 0.0, end, carry)) {
        for (int k = 0; k < 4; ++k) next_changed[v[k]] = dirty[v[k]] = 1;
      }
    });
    report.hits += hits;
    if (hits == 0) break;
    ++report.rounds;
    changed.swap(next_changed);
  }
  return report;
}

ImpactReport stopImpacts(const std::vector<PairContact>& contacts, const std::vector<char>& skip,
                         const CollisionStep& step, double thickness, int scaled_rounds,
                         Points& end, Points* carry, const std::vector<char>* moved,
                         int threads) {
  ImpactReport report;
  const Points& start = step.start;
  const int n = static_cast<int>(end.cols());
  std::vector<double> scale;                   // this round's scale of each particle's motion
  std::vector<char> changed(n, 1), shortened(n, 0), next_changed(n, 0);
  if (moved != nullptr) changed = *moved;
  std::vector<int> touched;
  std::vector<CcdResult> results;
  for (std::size_t i = 0; i < contacts.size(); ++i) {
    if (!skip[i] && !(impactDistance(thickness, contacts[i].start_distance) > 1e-9 * thickness)) {
      ++report.touching;
    }
  }
  for (int round = 0;; ++round) {
    const bool stop_outright = round >= scaled_rounds;
    scale.assign(n, 1.0);
    touched.clear();
    // A round only marks scales: every pair is tested on the round's end as it was.
    const int hits = forEachImpact(contacts, skip, changed, start, end, thickness, threads,
                                   nullptr, results, report.tests,
                                   [&](const PairContact& c, const CcdResult& ccd) {
      const auto& v = c.pair.v;
      const double s = stop_outright ? 0.0 : ccd.safe_time;
      for (int k = 0; k < 4; ++k) {
        if (!step.movable[v[k]]) continue;
        if (scale[v[k]] == 1.0) touched.push_back(v[k]);
        scale[v[k]] = std::min(scale[v[k]], s);
      }
    });
    if (hits == 0) break;
    ++report.rounds;
    report.hits += hits;
    std::fill(next_changed.begin(), next_changed.end(), 0);
    int moved = 0;
    for (int v : touched) {
      const Vec3 motion = end.col(v) - start.col(v);
      if (scale[v] >= 1.0 || motion.isZero(0.0)) continue;
      const Vec3 to = start.col(v) + scale[v] * motion;
      if (carry != nullptr) carry->col(v) += to - end.col(v);
      end.col(v) = to;
      next_changed[v] = 1;
      shortened[v] = 1;
      ++moved;
    }
    if (moved == 0) {  // every colliding pair is stopped or pinned: nothing left to shorten
      report.unresolved = hits;
      break;
    }
    changed.swap(next_changed);
  }
  report.shortened = static_cast<int>(std::count(shortened.begin(), shortened.end(), 1));
  return report;
}

}  // namespace cloth_sim
