#include "cloth_sim/core/collision/sphere_impacts.h"

#include <algorithm>
#include <cmath>

namespace cloth_sim {
namespace {

constexpr int kSweeps = 4;

/// Body properties seen by an impulse: zero inverse mass/inertia for kinematic spheres.
struct Body {
  SphereCollider* s;
  double inv_mass;
  double inv_inertia;
  explicit Body(SphereCollider* sphere)
      : s(sphere),
        inv_mass(sphere->isDynamic() ? 1.0 / sphere->mass : 0.0),
        inv_inertia(sphere->isDynamic() ? 1.0 / sphere->inertia() : 0.0) {}
  /// Velocity of the body's material point at offset @p r from its centre.
  Vec3 pointVelocity(const Vec3& r) const { return s->velocity + s->angular_velocity.cross(r); }
  void applyImpulse(const Vec3& impulse, const Vec3& r) {
    s->velocity += inv_mass * impulse;
    s->angular_velocity += inv_inertia * r.cross(impulse);
  }
};

/// Normal then friction impulse between @p a and @p b (b may be the ground: a still body with
/// no inverse mass). @p n points from b to a; @p ra, @p rb are the contact point from each
/// centre. Returns whether they were approaching.
bool impact(Body& a, Body* b, const Vec3& n, const Vec3& ra, const Vec3& rb, double restitution,
            double mu, double resting_speed) {
  const Vec3 v_rel = a.pointVelocity(ra) - (b ? b->pointVelocity(rb) : Vec3::Zero());
  const double vn = v_rel.dot(n);
  if (vn >= 0.0) return false;
  if (-vn < resting_speed) restitution = 0.0;
  const double inv_b = b ? b->inv_mass : 0.0;
  const double normal_impulse = -(1.0 + restitution) * vn / (a.inv_mass + inv_b);
  a.applyImpulse(normal_impulse * n, ra);
  if (b) b->applyImpulse(-normal_impulse * n, rb);
  // Friction on the slip: tangential effective mass includes the spin response r x t (|r| = R).
  const Vec3 slip = v_rel - vn * n;
  const double speed = slip.norm();
  if (mu <= 0.0 || speed < 1e-12) return true;
  const double k = a.inv_mass + inv_b + ra.squaredNorm() * a.inv_inertia +
                   (b ? rb.squaredNorm() * b->inv_inertia : 0.0);
  const double stop = speed / k;
  const Vec3 friction = -std::min(stop, mu * normal_impulse) * slip / speed;
  a.applyImpulse(friction, ra);
  if (b) b->applyImpulse(-friction, rb);
  return true;
}

}  // namespace

int resolveSphereImpacts(Colliders& colliders, double resting_speed) {
  std::vector<SphereCollider>& spheres = colliders.mutableSpheres();
  const GroundPlane& ground = colliders.ground();
  int contacts = 0;
  for (int sweep = 0; sweep < kSweeps; ++sweep) {
    for (std::size_t i = 0; i < spheres.size(); ++i) {
      Body a(&spheres[i]);
      for (std::size_t j = i + 1; j < spheres.size(); ++j) {
        Body b(&spheres[j]);
        if (a.inv_mass + b.inv_mass == 0.0) continue;  // two kinematic spheres pass through
        const Vec3 d = a.s->center - b.s->center;
        const double dist = d.norm(), reach = a.s->radius + b.s->radius;
        if (dist >= reach) continue;
        const Vec3 n = dist > 1e-12 ? Vec3(d / dist) : Vec3::UnitZ();
        const double share = (reach - dist) / (a.inv_mass + b.inv_mass);
        a.s->center += share * a.inv_mass * n;
        b.s->center -= share * b.inv_mass * n;
        impact(a, &b, n, -a.s->radius * n, b.s->radius * n,
               std::max(a.s->restitution, b.s->restitution), std::max(a.s->friction, b.s->friction),
               resting_speed);
        if (sweep == 0) ++contacts;
      }
      if (ground.enabled && a.inv_mass > 0.0 && a.s->center.z() - a.s->radius < ground.height) {
        a.s->center.z() = ground.height + a.s->radius;
        impact(a, nullptr, Vec3::UnitZ(), -a.s->radius * Vec3::UnitZ(), Vec3::Zero(),
               a.s->restitution, ground.friction, resting_speed);
        if (sweep == 0) ++contacts;
      }
    }
  }
  return contacts;
}

}  // namespace cloth_sim
