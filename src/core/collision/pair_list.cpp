#include "cloth_sim/core/collision/pair_list.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "cloth_sim/core/collision/primitive_distance.h"

namespace cloth_sim {

PairList::PairList(const PairSearch& tree, double margin) : tree_(tree), margin_(margin) {
  if (!(margin > 0.0)) throw std::invalid_argument("pair list: the margin must be > 0 m");
}

bool PairList::find(PairSearch& search, const SurfaceTopology& topology, const Points& start,
                    const Points& end, double reach, double edge_reach,
                    std::vector<PairCandidate>& out) {
  out.clear();
  const int n = static_cast<int>(start.cols());
  const double m2 = margin_ * margin_;
  bool fits = true;
  for (int i = 0; i < n && fits; ++i) fits = (end.col(i) - start.col(i)).squaredNorm() <= 4.0 * m2;
  if (!fits) {
    search.find(topology, start, end, reach, edge_reach, out);
    return false;
  }
  bool all = anchor_.cols() != n || reach != reach_ || edge_reach != edge_reach_;
  touched_.assign(n, all ? 1 : 0);
  anchored_ = all ? n : 0;
  if (!all) {
    for (int i = 0; i < n; ++i) {
      if ((start.col(i) - anchor_.col(i)).squaredNorm() > m2 ||
          (end.col(i) - anchor_.col(i)).squaredNorm() > m2) {
        touched_[i] = 1;
        ++anchored_;
      }
    }
    if (anchored_ > n / 4) {
      all = true;
      anchored_ = n;
      touched_.assign(n, 1);
    }
  }
  if (all) anchor_.resize(3, n);
  if (anchored_ > 0) {
    for (int i = 0; i < n; ++i) {
      if (touched_[i]) anchor_.col(i) = 0.5 * (start.col(i) + end.col(i));
    }
    relist(topology, reach, edge_reach, all);
  }
  filter(start, end, reach, edge_reach, out);
  return true;
}

void PairList::relist(const SurfaceTopology& topology, double reach, double edge_reach,
                      bool all) {
  const double grow = 2.0 * margin_;
  if (all) {
    listed_.clear();
    tree_.findTouching(topology, anchor_, reach + grow, edge_reach + grow, margin_, nullptr,
                       found_);
    reach_ = reach;
    edge_reach_ = edge_reach;
  } else {
    const auto touches = [&](const Listed& l) {
      const auto& v = l.pair.v;
      return touched_[v[0]] || touched_[v[1]] || touched_[v[2]] || touched_[v[3]];
    };
    listed_.erase(std::remove_if(listed_.begin(), listed_.end(), touches), listed_.end());
    tree_.findTouching(topology, anchor_, reach + grow, edge_reach + grow, margin_, &touched_,
                       found_);
  }
  // The exact distance at the anchors; a part in 1e9 more, so that rounding keeps a pair at
  // the bound.
  const double vertex_bound = (reach + grow) * (1.0 + 1e-9);
  const double edge_bound = (edge_reach + grow) * (1.0 + 1e-9);
  for (const PairCandidate& p : found_) {
    const PairPoints x{anchor_.col(p.v[0]), anchor_.col(p.v[1]), anchor_.col(p.v[2]),
                       anchor_.col(p.v[3])};
    const double bound = p.kind == PairKind::kVertexTriangle ? vertex_bound : edge_bound;
    const double distance = closestPoints(p.kind, x).distance;
    if (distance <= bound) listed_.push_back({p, distance});
  }
}

void PairList::filter(const Points& start, const Points& end, double reach, double edge_reach,
                      std::vector<PairCandidate>& out) {
  // Each vertex's farthest from its anchor over the substep: a primitive's points are no farther
  // from their places at the anchors than its farthest vertex, so a pair whose distance there,
  // less both primitives' farthest, exceeds its reach stays out of reach over the substep.
  const int n = static_cast<int>(start.cols());
  away_.resize(n);
  for (int i = 0; i < n; ++i) {
    away_[i] = std::sqrt(std::max((start.col(i) - anchor_.col(i)).squaredNorm(),
                                  (end.col(i) - anchor_.col(i)).squaredNorm()));
  }
  lo_ = start.cwiseMin(end);
  hi_ = start.cwiseMax(end);
  for (const Listed& l : listed_) {
    const PairCandidate& p = l.pair;
    const auto& v = p.v;
    const bool vt = p.kind == PairKind::kVertexTriangle;
    const double gap = vt ? reach : edge_reach;
    // First primitive: the vertex v[0] or the edge (v[0], v[1]); second: the rest.
    const double away_a = vt ? away_[v[0]] : std::max(away_[v[0]], away_[v[1]]);
    const double away_b = std::max(std::max(away_[v[2]], away_[v[3]]), vt ? away_[v[1]] : 0.0);
    if (l.distance - away_a - away_b > gap * (1.0 + 1e-9)) continue;
    Vec3 lo_a = lo_.col(v[0]), hi_a = hi_.col(v[0]);
    if (!vt) {
      lo_a = lo_a.cwiseMin(lo_.col(v[1]));
      hi_a = hi_a.cwiseMax(hi_.col(v[1]));
    }
    Vec3 lo_b = lo_.col(v[2]).cwiseMin(lo_.col(v[3]));
    Vec3 hi_b = hi_.col(v[2]).cwiseMax(hi_.col(v[3]));
    if (vt) {
      lo_b = lo_b.cwiseMin(lo_.col(v[1]));
      hi_b = hi_b.cwiseMax(hi_.col(v[1]));
    }
    if ((lo_a.array() - gap <= hi_b.array()).all() && (lo_b.array() - gap <= hi_a.array()).all()) {
      out.push_back(p);
    }
  }
}

}  // namespace cloth_sim
