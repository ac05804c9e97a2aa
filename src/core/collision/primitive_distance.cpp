#include "cloth_sim/core/collision/primitive_distance.h"

#include <algorithm>
#include <cmath>

namespace cloth_sim {
namespace {

/// The triangle's closest point to p as barycentric weights (u, v, w) of (a, b, c), by the
/// Voronoi regions of its vertices, edges and face.
Vec3 closestWeights(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return Vec3(1, 0, 0);
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return Vec3(0, 1, 0);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    const double s = d1 / (d1 - d3);
    return Vec3(1.0 - s, s, 0.0);
  }
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return Vec3(0, 0, 1);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    const double s = d2 / (d2 - d6);
    return Vec3(1.0 - s, 0.0, s);
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
    const double s = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return Vec3(0.0, 1.0 - s, s);
  }
  const double sum = va + vb + vc;
  if (!(sum > 0.0)) return Vec3(1, 0, 0);  // degenerate: the regions above decided already
  return Vec3(va / sum, vb / sum, vc / sum);
}

}  // namespace

ClosestPoints pointTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 w = closestWeights(p, a, b, c);
  ClosestPoints out;
  out.weight = {1.0, -w.x(), -w.y(), -w.z()};
  out.distance = (p - (w.x() * a + w.y() * b + w.z() * c)).norm();
  return out;
}

ClosestPoints segmentSegment(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1) {
  const Vec3 d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  // Lengths below this (relative to the segments' scale) count as points.
  const double tiny = 1e-30 + 1e-24 * (a + e + r.squaredNorm());
  double s = 0.0, t = 0.0;
  if (a <= tiny && e <= tiny) {
    s = t = 0.0;
  } else if (a <= tiny) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = d1.dot(r);
    if (e <= tiny) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = d1.dot(d2), denom = a * e - b * b;
      // Parallel segments (denom ~ 0): any s; take 0 and let t and the clamps below decide.
      s = denom > 1e-14 * a * e ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0.0) {
        t = 0.0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (t > 1.0) {
        t = 1.0;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  ClosestPoints out;
  out.weight = {1.0 - s, s, -(1.0 - t), -t};
  out.distance = (p0 + s * d1 - (q0 + t * d2)).norm();
  return out;
}

}  // namespace cloth_sim
