// Contact of one particle with the rigid bodies over a step (collideWithBodies, body_collider.h):
// each body in turn in its own frame, then the squeeze between bodies.
#include <algorithm>
#include <cmath>
#include <vector>

#include "cloth_sim/core/collision/body_collider.h"
#include "cloth_sim/core/collision/contact_projection.h"

namespace cloth_sim {
namespace {

/// Bisection and golden-section steps: 2^-48 of the path, far below any margin.
constexpr int kSearchSteps = 48;
/// Balancing passes of a squeezed particle (each halves the imbalance between two bodies).
constexpr int kBalancePasses = 12;

/// m, distance beyond the shape grown by the margin (negative inside), body frame.
double gap(const BodyCollider& b, const Vec3& p) { return b.geometry.distance(p) - b.margin; }

/// Distance (m) from the origin to the segment a -> e.
double segmentDistanceToOrigin(const Vec3& a, const Vec3& e) {
  const Vec3 d = e - a;
  const double len2 = d.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp(-a.dot(d) / len2, 0.0, 1.0) : 0.0;
  return (a + t * d).norm();
}

/// @p p moved along @p n (unit) to where it leaves the grown shape: the grown shape is convex, so
/// the ray from a point inside crosses its surface once.
Vec3 pushOut(const BodyCollider& b, const Vec3& p, const Vec3& n) {
  double lo = 0.0, hi = 2.0 * (b.geometry.boundingRadius() + b.margin) + p.norm();
  for (int k = 0; k < kSearchSteps; ++k) {
    const double mid = 0.5 * (lo + hi);
    (gap(b, p + mid * n) >= 0.0 ? hi : lo) = mid;
  }
  return p + hi * n;
}

/// First t in [0, 1] where a + t (e - a) enters the grown convex shape, or -1. The gap along a
/// segment is convex, so its minimum is found by golden section and the entry by bisection
/// before it.
double entry(const BodyCollider& b, const Vec3& a, const Vec3& e) {
  const auto f = [&](double t) { return gap(b, a + t * (e - a)); };
  double t_in = 1.0;
  if (f(1.0) >= 0.0) {
    constexpr double kGolden = 0.6180339887498949;
    double lo = 0.0, hi = 1.0;
    double x1 = hi - kGolden * (hi - lo), x2 = lo + kGolden * (hi - lo);
    double f1 = f(x1), f2 = f(x2);
    for (int k = 0; k < kSearchSteps; ++k) {
      if (f1 < 0.0 || f2 < 0.0) break;
      if (f1 <= f2) {
        hi = x2, x2 = x1, f2 = f1, x1 = hi - kGolden * (hi - lo), f1 = f(x1);
      } else {
        lo = x1, x1 = x2, f1 = f2, x2 = lo + kGolden * (hi - lo), f2 = f(x2);
      }
    }
    if (f1 >= 0.0 && f2 >= 0.0) return -1.0;
    t_in = f1 < 0.0 ? x1 : x2;
  }
  double lo = 0.0, hi = t_in;  // f(lo) >= 0 > f(hi)
  for (int k = 0; k < kSearchSteps; ++k) {
    const double mid = 0.5 * (lo + hi);
    (f(mid) >= 0.0 ? lo : hi) = mid;
  }
  return lo;
}

/// One particle against one convex body, in the body's frame: from @p a to @p e, with its free
/// motion @p free relative to the body. True if @p e changed.
bool collideConvex(const BodyCollider& b, const Vec3& a, Vec3& e, const std::optional<Vec3>& free) {
  if (segmentDistanceToOrigin(a, e) > b.geometry.boundingRadius() + b.margin) return false;
  if (gap(b, a) < 0.0) {
    // Started inside (the body was put onto the cloth, or a squeeze holds it): out along the
    // normal at the end, or at the start when the end is on the far side.
    if (gap(b, e) >= 0.0) return false;
    Vec3 n = b.geometry.gradient(e);
    const Vec3 n_start = b.geometry.gradient(a);
    if (n.dot(n_start) < 0.0) n = n_start;
    e = pushOut(b, e, n);
    return true;
  }
  const double t = entry(b, a, e);
  if (t < 0.0) return false;
  const Vec3 at = a + t * (e - a);
  const Vec3 n = b.geometry.gradient(at);
  // Keep the slide along the tangent plane at the entry point, drop the part into the body.
  Vec3 corrected = e - std::min(0.0, (e - at).dot(n)) * n;
  const double correction = (corrected - e).norm();
  corrected = a + applyFriction(corrected - a, n, frictionLoad(correction, n, free), b.friction);
  if (gap(b, corrected) < 0.0) corrected = pushOut(b, corrected, n);
  e = corrected;
  return true;
}

/// A body the particle overlaps at @p x (m, simulation frame): its outward normal there and
/// how deep the particle is inside its margin (m, >= 0).
struct Overlap {
  const BodyCollider* body;
  Vec3 normal;
  double depth;
};

/// The bodies whose margin @p x is within (touching counts, with depth 0).
std::vector<Overlap> overlaps(const std::vector<BodyCollider>& bodies, const Vec3& x) {
  std::vector<Overlap> out;
  for (const BodyCollider& b : bodies) {
    if (!b.placed) continue;
    const Eigen::Isometry3d pose = b.pose();
    const Vec3 local = pose.inverse() * x;
    if (b.geometry.shape == BodyShape::kMesh) {
      Vec3 point, normal;
      if (!b.geometry.mesh->nearest(local, b.margin, point, normal)) continue;
      const double depth = b.margin - (local - point).norm();
      if (depth >= -1e-12) out.push_back({&b, pose.linear() * normal, std::max(0.0, depth)});
      continue;
    }
    if (local.norm() > b.geometry.boundingRadius() + b.margin) continue;
    const double g = gap(b, local);
    if (g <= 1e-12) out.push_back({&b, pose.linear() * b.geometry.gradient(local), std::max(0.0, -g)});
  }
  return out;
}

/// Where body @p b's motion over the step carries a point fixed to it that was at @p p at the
/// start (m).
Vec3 carried(const BodyCollider& b, const Vec3& p) { return b.pose() * (b.previousPose().inverse() * p); }

/// A particle squeezed between bodies (inside the margin of one after another pushed it there):
/// balanced where the overlaps cancel, then held by friction pressing with the overlaps.
bool squeeze(const std::vector<BodyCollider>& bodies, const Vec3& start, Vec3& x) {
  std::vector<Overlap> touching = overlaps(bodies, x);
  if (touching.size() < 2) return false;
  const Vec3 before = x;
  for (int pass = 0; pass < kBalancePasses && touching.size() >= 2; ++pass) {
    Vec3 push = Vec3::Zero();
    for (const Overlap& o : touching) push += o.depth * o.normal;
    x += push / static_cast<double>(touching.size());
    touching = overlaps(bodies, x);
  }
  double grip = 0.0;  // m: sum of mu times the overlap of each body pressing on the particle
  Vec3 motion = Vec3::Zero();
  for (const Overlap& o : touching) {
    grip += o.body->friction * o.depth;
    motion += carried(*o.body, start) - start;
  }
  if (touching.size() >= 2 && grip > 0.0) {
    motion /= static_cast<double>(touching.size());
    const Vec3 slide = applyFriction(x - start - motion, touching.front().normal, grip, 1.0);
    x = start + motion + slide;
  }
  return x != before;
}

}  // namespace

bool collideWithBodies(const std::vector<BodyCollider>& bodies, const Vec3& start, Vec3& end,
                       const std::optional<Vec3>& free_motion) {
  if (bodies.empty()) return false;
  const Vec3 original = end;
  for (const BodyCollider& b : bodies) {
    if (!b.placed) continue;  // on a frame not seen yet: nowhere
    const Eigen::Isometry3d pose = b.pose(), previous = b.previousPose();
    const Vec3 a = previous.inverse() * start;
    Vec3 e = pose.inverse() * end;
    std::optional<Vec3> free;  // relative to the body, in its frame
    if (free_motion) free = pose.linear().transpose() * (*free_motion - (carried(b, start) - start));
    const bool moved = b.geometry.shape == BodyShape::kMesh
                           ? b.geometry.mesh->collide(a, e, free)
                           : collideConvex(b, a, e, free);
    if (moved) end = pose * e;
  }
  squeeze(bodies, start, end);
  return end != original;
}

}  // namespace cloth_sim
