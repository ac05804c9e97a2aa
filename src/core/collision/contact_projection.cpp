#include "cloth_sim/core/collision/contact_projection.h"

#include <algorithm>
#include <cmath>

namespace cloth_sim {

Vec3 applyFriction(const Vec3& displacement, const Vec3& normal, double normal_correction,
                   double mu) {
  if (mu <= 0.0) return displacement;
  const Vec3 tangential = displacement - displacement.dot(normal) * normal;
  const double slide = tangential.norm();
  const double cut = mu * normal_correction;
  if (slide <= cut) return displacement - tangential;
  return displacement - (cut / slide) * tangential;
}

double frictionLoad(double correction, const Vec3& normal, const std::optional<Vec3>& free_motion) {
  if (!free_motion) return correction;
  return std::min(correction, std::max(0.0, -free_motion->dot(normal)));
}

Vec3 closestPointOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return a;
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return a + (d1 / (d1 - d3)) * ab;
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return a + (d2 / (d2 - d6)) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
    return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  }
  const double denom = 1.0 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

double sphereEntry(const Vec3& start, const Vec3& path, double radius) {
  const double a = path.squaredNorm(), b = start.dot(path), c = start.squaredNorm() - radius * radius;
  const double disc = b * b - a * c;
  if (a <= 0.0 || disc < 0.0) return -1.0;
  const double t = (-b - std::sqrt(disc)) / a;
  return t <= 1.0 ? t : -1.0;
}

double segmentTriangleCrossing(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b,
                               const Vec3& c) {
  const Vec3 dir = q - p, e1 = b - a, e2 = c - a;
  const Vec3 h = dir.cross(e2);
  const double det = e1.dot(h);
  if (std::abs(det) < 1e-300) return -1.0;
  const double inv = 1.0 / det;
  const Vec3 s = p - a;
  const double u = inv * s.dot(h);
  if (u < 0.0 || u > 1.0) return -1.0;
  const Vec3 qv = s.cross(e1);
  const double v = inv * dir.dot(qv);
  if (v < 0.0 || u + v > 1.0) return -1.0;
  const double t = inv * e2.dot(qv);
  return (t >= 0.0 && t <= 1.0) ? t : -1.0;
}

}  // namespace cloth_sim
