#include "cloth_sim/core/collision/triangle_intersection.h"

#include <cmath>

#include "cloth_sim/core/linalg/parallel.h"

namespace cloth_sim {
namespace {

/// Sign of the volume of tetrahedron (a, b, c, d) (orient3d), 0 when it is within the rounding
/// error of the double-precision product (about 1e-15 of |a-d| |b-d| |c-d|; 1e-12 kept as
/// margin): without it, two triangles of one flat but tilted sheet, coplanar up to rounding,
/// came out as crossing.
int orient(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const Vec3 ad = a - d, bd = b - d, cd = c - d;
  const double v = ad.dot(bd.cross(cd));
  const double scale = ad.norm() * bd.norm() * cd.norm();
  if (std::abs(v) <= 1e-12 * scale) return 0;
  return (v > 0.0) - (v < 0.0);
}

}  // namespace

bool segmentCrossesTriangle(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b,
                            const Vec3& c) {
  const int sp = orient(a, b, c, p), sq = orient(a, b, c, q);
  if (sp == 0 || sq == 0 || sp == sq) return false;
  // The line pq passes inside abc when it turns the same way round all three edges.
  const int s1 = orient(p, q, a, b), s2 = orient(p, q, b, c), s3 = orient(p, q, c, a);
  return s1 != 0 && s1 == s2 && s2 == s3;
}

bool trianglesIntersect(const Vec3& a0, const Vec3& a1, const Vec3& a2, const Vec3& b0,
                        const Vec3& b1, const Vec3& b2) {
  return segmentCrossesTriangle(a0, a1, b0, b1, b2) || segmentCrossesTriangle(a1, a2, b0, b1, b2) ||
         segmentCrossesTriangle(a2, a0, b0, b1, b2) || segmentCrossesTriangle(b0, b1, a0, a1, a2) ||
         segmentCrossesTriangle(b1, b2, a0, a1, a2) || segmentCrossesTriangle(b2, b0, a0, a1, a2);
}

IntersectionCounter::IntersectionCounter(Eigen::Matrix3Xi triangles)
    : triangles_(std::move(triangles)) {}

bool IntersectionCounter::adjacent(int s, int t) const {
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b)
      if (triangles_(a, s) == triangles_(b, t)) return true;
  return false;
}

bool IntersectionCounter::intersect(const Points& x, int s, int t) const {
  if (!boxes_[s].intersects(boxes_[t]) || adjacent(s, t)) return false;
  const auto v = [&](int k, int tri) { return Vec3(x.col(triangles_(k, tri))); };
  return trianglesIntersect(v(0, s), v(1, s), v(2, s), v(0, t), v(1, t), v(2, t));
}

std::vector<std::pair<int, int>> IntersectionCounter::pairs(const Points& positions) {
  std::vector<std::pair<int, int>> out;
  find(positions, &out);
  return out;
}

std::size_t IntersectionCounter::find(const Points& x, std::vector<std::pair<int, int>>* out) {
  const int n = static_cast<int>(triangles_.cols());
  if (n == 0 || !x.allFinite()) return 0;
  boxes_.resize(n);
  keys_.resize(3, n);
  // Triangles in fixed blocks on the threads; sums and pairs gathered in block order, so the
  // count and the pairs (and their order) are the serial ones on any number of threads.
  const BlockSplit split(static_cast<std::size_t>(n), 512);
  const double mean_size = orderedSum(threads_, split.blocks(), [&](int b) {
    double sum = 0.0;
    for (std::size_t t = split.begin(b); t < split.end(b); ++t) {
      Eigen::AlignedBox3d box(Vec3(x.col(triangles_(0, t))));
      box.extend(Vec3(x.col(triangles_(1, t))));
      box.extend(Vec3(x.col(triangles_(2, t))));
      boxes_[t] = box;
      keys_.col(t) = box.min();
      sum += box.sizes().maxCoeff();
    }
    return sum;
  });
  const double cell = std::max(2.0 * mean_size / n, 1e-9);
  oversize_.clear();
  is_oversize_.assign(n, 0);
  for (int t = 0; t < n; ++t) {
    if (boxes_[t].sizes().maxCoeff() > cell) {
      oversize_.push_back(t);
      is_oversize_[t] = 1;
    }
  }
  hash_.build(keys_, cell);
  std::vector<std::vector<std::pair<int, int>>> found(split.blocks());
  const Vec3 reach = Vec3::Constant(cell);
  parallelFor(threads_, split.blocks(), [&](int b) {
    for (int s = static_cast<int>(split.begin(b)); s < static_cast<int>(split.end(b)); ++s) {
      if (is_oversize_[s]) continue;
      const Eigen::AlignedBox3d query(boxes_[s].min() - reach, boxes_[s].max());
      hash_.query(query, [&](int t) {
        if (t > s && !is_oversize_[t] && intersect(x, s, t)) found[b].emplace_back(s, t);
      });
    }
  });
  // A pair with an oversize triangle: from its smaller oversize end.
  std::vector<std::vector<std::pair<int, int>>> large(oversize_.size());
  parallelFor(threads_, static_cast<int>(oversize_.size()), [&](int k) {
    const int s = oversize_[k];
    for (int t = 0; t < n; ++t) {
      if (t == s || (is_oversize_[t] && t < s)) continue;
      if (intersect(x, s, t)) large[k].emplace_back(s, t);
    }
  });
  std::size_t count = 0;
  for (const auto* lists : {&found, &large}) {
    for (const auto& list : *lists) {
      count += list.size();
      if (out == nullptr) continue;
      for (const auto& [s, t] : list) out->emplace_back(std::min(s, t), std::max(s, t));
    }
  }
  return count;
}

}  // namespace cloth_sim
