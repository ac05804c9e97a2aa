#include "cloth_sim/core/collision/particle_self_contact.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "cloth_sim/core/collision/contact_projection.h"

namespace cloth_sim {

ParticleSelfContact::ParticleSelfContact(const Eigen::Matrix3Xi& triangles, const Points& rest,
                                         double thickness, double friction)
    : thickness_(thickness), friction_(friction), rest_(rest) {
  const int n = static_cast<int>(rest.cols());
  std::vector<std::vector<int>> ring(n);
  for (Eigen::Index t = 0; t < triangles.cols(); ++t) {
    for (int a = 0; a < 3; ++a) {
      const int i = triangles(a, t), j = triangles((a + 1) % 3, t);
      if (i < 0 || i >= n || j < 0 || j >= n) {
        throw std::invalid_argument("self-contact: triangle " + std::to_string(t) +
                                    " has a vertex out of range");
      }
      ring[i].push_back(j);
      ring[j].push_back(i);
    }
  }
  ring_start_.assign(n + 1, 0);
  for (int i = 0; i < n; ++i) {
    std::sort(ring[i].begin(), ring[i].end());
    ring[i].erase(std::unique(ring[i].begin(), ring[i].end()), ring[i].end());
    ring_start_[i + 1] = ring_start_[i] + static_cast<int>(ring[i].size());
  }
  ring_.reserve(ring_start_[n]);
  for (const auto& r : ring) ring_.insert(ring_.end(), r.begin(), r.end());
  if (!(thickness_ > 0.0)) throw std::invalid_argument("self-contact: thickness must be > 0 m");
}

double ParticleSelfContact::minimumThickness(const Eigen::Matrix3Xi& triangles,
                                             const Points& rest) {
  double widest = 0.0;
  for (Eigen::Index t = 0; t < triangles.cols(); ++t) {
    const Vec3 a = rest.col(triangles(0, t)), b = rest.col(triangles(1, t)),
               c = rest.col(triangles(2, t));
    const double la = (b - c).squaredNorm(), lb = (c - a).squaredNorm(), lc = (a - b).squaredNorm();
    const double longest = std::max({la, lb, lc});
    double hole = 0.5 * std::sqrt(longest);  // obtuse or right: the longest side's midpoint
    if (2.0 * longest < la + lb + lc) {      // acute: the circumradius abc / (4 area)
      const double area2 = (b - a).cross(c - a).norm();
      if (area2 > 0.0) hole = std::sqrt(la * lb * lc) / (2.0 * area2);
    }
    widest = std::max(widest, hole);
  }
  return 1.05 * widest;
}

bool ParticleSelfContact::neighbours(int i, int j) const {
  return std::binary_search(ring_.begin() + ring_start_[i], ring_.begin() + ring_start_[i + 1], j);
}

void ParticleSelfContact::findPairs(const Points& x, double margin) {
  pairs_.clear();
  const double reach = thickness_ + margin, reach2 = reach * reach;
  // Cells of twice the reach: a query box spans at most 2 cells a side (8 cells, not 27).
  hash_.build(x, 2.0 * reach);
  const Vec3 half = Vec3::Constant(reach);
  // Particles in fixed blocks on the threads; the pairs appended in block order (the serial one).
  const BlockSplit split(static_cast<std::size_t>(x.cols()), 256);
  std::vector<std::vector<Pair>> found(split.blocks());
  parallelFor(threads_, split.blocks(), [&](int b) {
    for (Eigen::Index i = split.begin(b); i < static_cast<Eigen::Index>(split.end(b)); ++i) {
      const Vec3 xi = x.col(i);
      hash_.query(Eigen::AlignedBox3d(xi - half, xi + half), [&](int j) {
        if (j <= i) return;
        const double dist2 = (x.col(j) - xi).squaredNorm();
        if (dist2 >= reach2 || neighbours(static_cast<int>(i), j)) return;
        // Pairs closer than t on the cloth at rest are the springs' business: as contacts they
        // fought the springs wherever the cloth compressed (a 2-ring pair at its rest distance,
        // t = its rest length, pushed at every substep, and the cloth blew up). Others get 20 %
        // compression before they touch.
        const double rest = (rest_.col(i) - rest_.col(j)).norm();
        if (rest < thickness_) return;
        const double d = std::min(thickness_, 0.8 * rest);
        if (dist2 < (d + margin) * (d + margin)) found[b].push_back({static_cast<int>(i), j, d});
      });
    }
  });
  for (const auto& block : found) pairs_.insert(pairs_.end(), block.begin(), block.end());
}

std::vector<std::pair<int, int>> ParticleSelfContact::contacts(const Points& positions) {
  findPairs(positions, 0.0);
  built_at_.resize(3, 0);  // the list is not resolve's any more
  std::vector<std::pair<int, int>> out;
  for (const Pair& p : pairs_) out.emplace_back(p.i, p.j);
  return out;
}

int ParticleSelfContact::limitDisplacement(const CollisionStep& step, Points& end,
                                   Points& velocities) const {
  const double cap = maxDisplacement();
  int limited = 0;
  for (Eigen::Index i = 0; i < end.cols(); ++i) {
    if (!step.movable[i]) continue;
    const Vec3 move = end.col(i) - step.start.col(i);
    const double length = move.norm();
    if (!(length > cap)) continue;  // also leaves a non-finite move to the step's check
    const Vec3 capped = move * (cap / length);
    velocities.col(i) += (capped - move) / step.h;
    end.col(i) = step.start.col(i) + capped;
    ++limited;
  }
  return limited;
}

int ParticleSelfContact::resolve(const CollisionStep& step, const GroundPlane& ground, Points& end,
                         Points& velocities) {
  if (!end.allFinite()) return 0;  // the step's check rolls this frame back
  before_ = end;
  // A Verlet list (as in molecular dynamics): the pairs within their distance plus a skin of
  // 0.5 t stay the candidates until some particle has moved 0.2 t from where the list was
  // built; two particles then have approached by at most 0.4 t, and the sweeps have 0.1 t to
  // spare. A pile at rest keeps its list; a falling cloth rebuilds it every substep.
  const double skin = 0.5 * thickness_;
  if (built_at_.cols() != end.cols() ||
      (end - built_at_).colwise().squaredNorm().maxCoeff() > 0.04 * thickness_ * thickness_) {
    findPairs(end, skin);
    built_at_ = end;
    ++rebuilds_;
  }
  // The sweeps visit only the pairs near contact now (within 0.1 t of it): most of the list
  // is the skin.
  active_.clear();
  for (const Pair& p : pairs_) {
    const double reach = p.distance + 0.1 * thickness_;
    if ((end.col(p.i) - end.col(p.j)).squaredNorm() < reach * reach) active_.push_back(p);
  }
  if (active_.empty()) return 0;
  const auto weight = [&](int i) { return step.movable[i] ? 1.0 / step.mass[i] : 0.0; };
  for (int sweep = 0; sweep < 4; ++sweep) {
    for (const Pair& p : active_) {
      const double wi = weight(p.i), wj = weight(p.j), w = wi + wj;
      if (w == 0.0) continue;
      Vec3 n = end.col(p.i) - end.col(p.j);
      const double dist = n.norm();
      if (dist >= p.distance) continue;
      if (dist > 1e-12 * p.distance) {
        n /= dist;
      } else {  // on top of each other: apart along where they came from
        n = step.start.col(p.i) - step.start.col(p.j);
        n = n.norm() > 0.0 ? Vec3(n.normalized()) : Vec3::UnitZ();
      }
      const double correction = p.distance - dist;
      end.col(p.i) += (wi / w * correction) * n;
      end.col(p.j) -= (wj / w * correction) * n;
      // Friction on the relative slide of the two over the substep.
      const Vec3 slide =
          (end.col(p.i) - step.start.col(p.i)) - (end.col(p.j) - step.start.col(p.j));
      const Vec3 kept = applyFriction(slide, n, correction, friction_);
      const Vec3 cut = slide - kept;
      end.col(p.i) -= (wi / w) * cut;
      end.col(p.j) += (wj / w) * cut;
    }
    if (ground.enabled) {
      for (Eigen::Index i = 0; i < end.cols(); ++i) {
        if (step.movable[i] && end(2, i) < ground.height) end(2, i) = ground.height;
      }
    }
  }
  int moved = 0;
  for (Eigen::Index i = 0; i < end.cols(); ++i) {
    const Vec3 delta = end.col(i) - before_.col(i);
    if (delta.isZero(0.0)) continue;
    velocities.col(i) += delta / step.h;
    ++moved;
  }
  return moved;
}

}  // namespace cloth_sim
