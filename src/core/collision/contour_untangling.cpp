#include "cloth_sim/core/collision/contour_untangling.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "cloth_sim/core/collision/triangle_intersection.h"

namespace cloth_sim {
namespace {

Vec3 unitNormal(const Points& x, const Eigen::Matrix3Xi& tri, int t) {
  const Vec3 a = x.col(tri(0, t)), b = x.col(tri(1, t)), c = x.col(tri(2, t));
  const Vec3 n = (b - a).cross(c - a);
  const double length = n.norm();
  return length > 0.0 ? Vec3(n / length) : Vec3::Zero();
}

/// The descent direction G of the contour's length for edge @p e crossing triangle @p t (see
/// contourDisplacement), or zero.
Vec3 descent(const SurfaceTopology& topology, const Points& x, int e, int t) {
  const Eigen::Matrix3Xi& tri = topology.triangles();
  const Vec3 n = unitNormal(x, tri, t);
  const auto& edge = topology.edge(e);
  const Vec3 p = x.col(edge[0]), u = x.col(edge[1]) - p;
  const double un = u.dot(n), uu = u.squaredNorm();
  if (!(std::abs(un) > 1e-9 * std::sqrt(uu))) return Vec3::Zero();  // E in T's plane
  Vec3 r_sum = Vec3::Zero();
  for (int face : topology.edgeFaces(e)) {
    if (face < 0) continue;
    int w = -1;
    for (int k = 0; k < 3; ++k) {
      if (tri(k, face) != edge[0] && tri(k, face) != edge[1]) w = tri(k, face);
    }
    Vec3 r = unitNormal(x, tri, face).cross(n);
    const double length = r.norm();
    if (w < 0 || !(length > 1e-12)) continue;  // F parallel to T: no direction within it
    r /= length;
    const Vec3 into = (x.col(w) - p) - u * (u.dot(x.col(w) - p) / uu);  // into F, across E
    r_sum += r.dot(into) >= 0.0 ? r : Vec3(-r);
  }
  return r_sum - n * (u.dot(r_sum) / un);
}

}  // namespace

int contourDisplacement(const SurfaceTopology& topology, const Points& x,
                        const std::vector<std::pair<int, int>>& pairs,
                        const std::vector<char>& movable, double step_length, Points& displacement) {
  const Eigen::Matrix3Xi& tri = topology.triangles();
  std::vector<std::pair<int, int>> crossings;  // (edge, triangle)
  for (const auto& [s, t] : pairs) {
    for (int side = 0; side < 2; ++side) {
      const int from = side == 0 ? s : t, through = side == 0 ? t : s;
      const Vec3 a = x.col(tri(0, through)), b = x.col(tri(1, through)), c = x.col(tri(2, through));
      for (int k = 0; k < 3; ++k) {
        const int i = tri(k, from), j = tri((k + 1) % 3, from);
        if (segmentCrossesTriangle(x.col(i), x.col(j), a, b, c)) {
          crossings.emplace_back(topology.findEdge(i, j), through);
        }
      }
    }
  }
  std::sort(crossings.begin(), crossings.end());  // an edge is in two triangles of a pair list
  crossings.erase(std::unique(crossings.begin(), crossings.end()), crossings.end());
  displacement.setZero(3, x.cols());
  for (const auto& [e, t] : crossings) {
    if (e < 0) continue;
    const Vec3 g = descent(topology, x, e, t);
    const double length = g.norm();
    if (!(length > 0.0) || !std::isfinite(length)) continue;
    const Vec3 unit = g / length;
    for (int v : topology.edge(e)) displacement.col(v) += unit;
    for (int k = 0; k < 3; ++k) displacement.col(tri(k, t)) -= unit;
  }
  for (Eigen::Index v = 0; v < displacement.cols(); ++v) {
    const double length = displacement.col(v).norm();
    if (!movable[v] || length == 0.0) {
      displacement.col(v).setZero();
      continue;
    }
    displacement.col(v) *= step_length / std::max(1.0, length);
  }
  return static_cast<int>(crossings.size());
}

}  // namespace cloth_sim
