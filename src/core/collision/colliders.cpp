#include "cloth_sim/core/collision/colliders.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "cloth_sim/core/collision/contact_projection.h"
#include "cloth_sim/core/collision/spatial_hash.h"
#include "cloth_sim/core/settings/settings_table.h"

namespace cloth_sim {
namespace {

/// Overlap (fraction of the radius) a particle may keep with a dynamic sphere whose contacts
/// were solved with the step: the half-space linearisation of the sphere leaves a vertex next
/// to a contact point up to about (spacing / 2)^2 / (2 r) inside it.
constexpr double kShallowOverlap = 0.05;

void checkSphere(const SphereCollider& s) {
  if (!s.center.allFinite()) throw std::invalid_argument("sphere center must be finite");
  if (!s.velocity.allFinite()) throw std::invalid_argument("sphere velocity must be finite");
  if (!s.angular_velocity.allFinite()) {
    throw std::invalid_argument("sphere angular velocity must be finite");
  }
  settings::kSphereRadius.require(s.radius, "sphere radius");
  settings::kFriction.require(s.friction, "sphere friction");
  settings::kSphereMass.require(s.mass, "sphere mass");
  settings::kRestitution.require(s.restitution, "sphere restitution");
}

/// Contact of one particle with one sphere over a step, in the frame that translates with the
/// sphere: @p rel_start / @p rel_end are the particle relative to the old / new centre.
/// Returns true and fixes @p rel_end if the relative path entered the sphere. @p surface_slip
/// (m) is how far the spin moved the sphere's surface during the step, as a function of the
/// contact normal: friction acts on the particle's slide relative to that surface.
template <typename SurfaceSlip>
bool collideSphere(const Vec3& rel_start, Vec3& rel_end, double radius, double mu,
                   SurfaceSlip&& surface_slip, const std::optional<Vec3>& free_motion) {
  const double r2 = radius * radius;
  const Vec3 path = rel_end - rel_start;
  Vec3 corrected;
  if (rel_start.squaredNorm() >= r2) {
    // Started outside: first crossing of the path with the sphere, if any (continuous test).
    const double t = sphereEntry(rel_start, path, radius);
    if (t < 0.0) return false;
    const Vec3 normal = (rel_start + t * path) / radius;
    // Keep the motion along the tangent plane at the entry point, drop the part into it.
    corrected = rel_end - std::min(0.0, (rel_end - (rel_start + t * path)).dot(normal)) * normal;
  } else {
    // Started inside (a sphere spawned or teleported onto the cloth, or a particle that
    // rounding left just inside the surface): push the end out radially, which keeps its
    // motion along the surface, unless the end is on the far side; then push out where the
    // particle was at the start, so a sphere that moves on cannot carry it through to its back.
    if (rel_end.squaredNorm() >= r2) return false;
    corrected = rel_end.dot(rel_start) > 0.0 || rel_start.squaredNorm() <= 1e-24 ? rel_end : rel_start;
  }
  const double len = corrected.norm();
  const Vec3 normal = len > 1e-12 ? Vec3(corrected / len) : Vec3::UnitZ();
  corrected = radius * normal;  // on the surface
  const double normal_correction = (corrected - rel_end).norm();
  const Vec3 slip = surface_slip(normal);
  const Vec3 moved = slip + applyFriction(corrected - rel_start - slip, normal,
                                          frictionLoad(normal_correction, normal, free_motion), mu);
  const Vec3 with_friction = rel_start + moved;
  const double with_len = with_friction.norm();
  rel_end = with_len > 1e-12 && with_len < radius ? Vec3(radius * with_friction / with_len)
                                                  : with_friction;
  return true;
}

/// Reaction accumulated on a dynamic sphere during one contact pass.
struct SphereReaction {
  Vec3 impulse = Vec3::Zero();          ///< N s
  Vec3 angular_impulse = Vec3::Zero();  ///< N m s, about the centre
};

/// Spheres as candidates for a particle: all of them when few, else through a hash grid of their
/// swept boxes (rebuilt every step), so many spheres do not cost particles x spheres.
class SphereCandidates {
 public:
  SphereCandidates(const std::vector<SphereCollider>& spheres, double h) : spheres_(spheres) {
    if (spheres.size() <= kDirect) {
      for (const auto& s : spheres) boxes_.push_back(sweptBox(s, h));
      return;
    }
    double largest = 0.0;
    for (const auto& s : spheres) largest = std::max(largest, s.radius + h * s.velocity.norm());
    hash_ = SpatialHash(2.0 * largest);
    for (std::size_t k = 0; k < spheres.size(); ++k) hash_.insert(static_cast<int>(k), sweptBox(spheres[k], h));
  }
  template <typename Visit>
  void forEach(const Vec3& a, const Vec3& b, Visit&& visit) const {
    Eigen::AlignedBox3d box;
    box.extend(a).extend(b);
    if (spheres_.size() <= kDirect) {
      for (std::size_t k = 0; k < spheres_.size(); ++k) {
        if (boxes_[k].intersects(box)) visit(k);
      }
      return;
    }
    hash_.query(box, [&](int k) { visit(static_cast<std::size_t>(k)); });
  }

 private:
  static constexpr std::size_t kDirect = 8;
  static Eigen::AlignedBox3d sweptBox(const SphereCollider& s, double h) {
    Eigen::AlignedBox3d box;
    box.extend(s.center).extend(Vec3(s.center - h * s.velocity));
    box.min().array() -= s.radius;
    box.max().array() += s.radius;
    return box;
  }
  const std::vector<SphereCollider>& spheres_;
  std::vector<Eigen::AlignedBox3d> boxes_;  ///< few spheres: each one's swept box
  SpatialHash hash_;
};

/// Particle @p i (its step from step.start to @p end) against every sphere whose swept box its
/// path meets: moved out of each it entered, by the whole correction for a kinematic sphere, by
/// the mass share M/(M+m) for a dynamic one, which gets the opposite impulse in @p reactions.
/// Returns whether any sphere moved it.
bool collideWithSpheres(const CollisionStep& step, const std::vector<SphereCollider>& spheres,
                        const SphereCandidates& candidates, bool in_solve_contacts,
                        Eigen::Index i, Points& end, std::vector<SphereReaction>& reactions,
                        Vec3& normal) {
  const double h = step.h;
  const Points& start = step.start;
  bool hit = false;
  candidates.forEach(start.col(i), end.col(i), [&](std::size_t k) {
    const SphereCollider& s = spheres[k];
    const Vec3 old_center = s.center - h * s.velocity;
    Vec3 rel_end = end.col(i) - s.center;
    // A dynamic sphere's contacts were solved with the step (ContactForces), against its
    // triangles linearised as half-spaces: leave the small overlap that linearisation allows
    // (correcting it here fought the solved forces); catch only what the solve missed.
    if (s.isDynamic() && in_solve_contacts && rel_end.norm() > (1.0 - kShallowOverlap) * s.radius &&
        (start.col(i) - old_center).norm() > s.radius) {
      return;
    }
    const auto slip = [&](const Vec3& n) { return Vec3(h * s.angular_velocity.cross(s.radius * n)); };
    std::optional<Vec3> rel_motion = step.freeMotion(i);
    if (rel_motion) *rel_motion -= s.center - old_center;
    if (!collideSphere(start.col(i) - old_center, rel_end, s.radius, s.friction, slip, rel_motion)) return;
    const Vec3 correction = s.center + rel_end - end.col(i);
    if (rel_end.norm() > 1e-12) normal = rel_end.normalized();
    if (s.isDynamic()) {
      // Share the correction by mass; the sphere takes the opposite impulse (applied later).
      const double share = s.mass / (s.mass + step.mass[i]);
      const Vec3 impulse = step.mass[i] * share * correction / h;
      reactions[k].impulse -= impulse;
      reactions[k].angular_impulse -= rel_end.cross(impulse);
      end.col(i) += share * correction;
    } else {
      end.col(i) += correction;
    }
    hit = true;
  });
  return hit;
}

/// Particle @p i lifted onto the @p ground (if on and below it), its slide along it cut by the
/// ground's friction (@p still_motion: its motion without the collision, see frictionLoad).
/// Returns whether it moved.
bool collideWithGround(const CollisionStep& step, const GroundPlane& ground,
                       const std::optional<Vec3>& still_motion, Eigen::Index i, Points& end,
                       Vec3& normal) {
  if (!(ground.enabled && end(2, i) < ground.height)) return false;
  normal = Vec3::UnitZ();
  const double depth = ground.height - end(2, i);
  end(2, i) = ground.height;
  end.col(i) = step.start.col(i) +
               applyFriction(end.col(i) - step.start.col(i), Vec3::UnitZ(),
                             frictionLoad(depth, Vec3::UnitZ(), still_motion), ground.friction);
  end(2, i) = std::max(end(2, i), ground.height);
  return true;
}

/// Particle @p i against each mesh obstacle in turn (MeshObstacle::collide keeps its start
/// side). Returns whether any moved it.
bool collideWithMeshes(const CollisionStep& step,
                       const std::vector<std::shared_ptr<const MeshObstacle>>& meshes,
                       const std::optional<Vec3>& still_motion, Eigen::Index i, Points& end,
                       Vec3& normal) {
  bool hit = false;
  for (const auto& mesh : meshes) {
    Vec3 moved = end.col(i);
    if (mesh->collide(step.start.col(i), moved, still_motion, &normal)) {
      end.col(i) = moved;
      hit = true;
    }
  }
  return hit;
}

/// The velocity of particle @p i after a collider moved its end from @p solved to @p end,
/// @p normal the collider's (unit, or zero when unknown). The integrator's own velocity is
/// (end - x_n) / h for implicit Euler, and for a multistep integrator (BDF2, h_i < h) the solved
/// velocity plus (end - solved) / h_i. Along the normal a contact is inelastic: a multistep
/// integrator would read the sudden stop as a deceleration and send the particle back up
/// (BDF2: at half its approach speed), so along it the velocity restarts as implicit Euler's,
/// (end - x_n) . n / h, and so does the history v_n (the next step then predicts it moving on
/// at that speed). Tangentially the motion keeps its order (a slide at constant deceleration
/// stays exact).
void restartAlong(const CollisionStep& step, const Vec3& normal, Eigen::Index i,
                  const Vec3& solved, const Vec3& end, Points& velocities) {
  const Vec3 euler = (end - step.start.col(i)) / step.h;
  if (step.implicit_h <= 0.0 || step.implicit_h == step.h) {
    velocities.col(i) = euler;
    return;
  }
  Vec3 v = velocities.col(i) + step.velocityGain() * (end - solved);
  v += normal * normal.dot(euler - v);
  velocities.col(i) = v;
  if (step.history_velocities != nullptr) {
    Points& history = *step.history_velocities;
    history.col(i) += normal * normal.dot(euler - Vec3(history.col(i)));
  }
}

/// Particle @p i against the rigid bodies (collideWithBodies). Returns whether they moved it.
bool collideWithBodyColliders(const CollisionStep& step, const BodySet& bodies, Eigen::Index i,
                              Points& end) {
  if (bodies.empty()) return false;
  Vec3 moved = end.col(i);
  if (!collideWithBodies(bodies.bodies(), step.start.col(i), moved, step.freeMotion(i))) return false;
  end.col(i) = moved;
  return true;
}

/// Each dynamic sphere takes the impulses of @p reactions (summed over the particles), and
/// then pushes out fully the particles its own move brought back into it.
void applySphereReactions(const CollisionStep& step, const std::vector<SphereReaction>& reactions,
                          bool in_solve_contacts, std::vector<SphereCollider>& spheres, Points& end,
                          Points& velocities) {
  const double h = step.h;
  for (std::size_t k = 0; k < spheres.size(); ++k) {
    SphereCollider& s = spheres[k];
    if (!s.isDynamic()) continue;
    const Vec3 dv = reactions[k].impulse / s.mass;
    s.velocity += dv;
    s.center += h * dv;  // the position change that goes with the velocity change
    s.angular_velocity += reactions[k].angular_impulse / s.inertia();
    // The sphere's own move above may have brought it back into a particle by a fraction m/M of
    // a correction: push such particles out fully; the sphere only takes the (tiny) impulse.
    for (Eigen::Index i = 0; i < end.cols(); ++i) {
      if (!step.movable[i]) continue;
      const Vec3 d = end.col(i) - s.center;
      const double dist = d.norm();
      const double allowed = in_solve_contacts ? (1.0 - kShallowOverlap) * s.radius : s.radius;
      if (dist >= allowed || dist < 1e-12) continue;
      const Vec3 push = (allowed - dist) * d / dist;
      end.col(i) += push;
      velocities.col(i) += push / h;  // along the normal: inelastic, as restartAlong
      s.velocity -= step.mass[i] * push / (h * s.mass);
    }
  }
}

}  // namespace

int Colliders::addSphere(const SphereCollider& sphere) {
  checkSphere(sphere);
  SphereCollider s = sphere;
  s.id = next_id_++;
  spheres_.push_back(s);
  return s.id;
}

void Colliders::removeSphere(int id) {
  auto it = std::find_if(spheres_.begin(), spheres_.end(),
                         [id](const SphereCollider& s) { return s.id == id; });
  if (it == spheres_.end()) throw std::invalid_argument("no sphere with id " + std::to_string(id));
  spheres_.erase(it);
}

void Colliders::moveSphere(int id, const Vec3& center, const Vec3& velocity) {
  auto it = std::find_if(spheres_.begin(), spheres_.end(),
                         [id](const SphereCollider& s) { return s.id == id; });
  if (it == spheres_.end()) throw std::invalid_argument("no sphere with id " + std::to_string(id));
  SphereCollider moved = *it;
  moved.center = center;
  moved.velocity = velocity;
  checkSphere(moved);
  it->center = center;
  it->velocity = velocity;
}

const SphereCollider* Colliders::findSphere(int id) const {
  auto it = std::find_if(spheres_.begin(), spheres_.end(),
                         [id](const SphereCollider& s) { return s.id == id; });
  return it == spheres_.end() ? nullptr : &*it;
}

void Colliders::setGround(const GroundPlane& ground) {
  if (!std::isfinite(ground.height)) throw std::invalid_argument("ground height must be finite");
  settings::kFriction.require(ground.friction, "ground friction");
  ground_ = ground;
}

void Colliders::addMesh(std::shared_ptr<const MeshObstacle> mesh) {
  if (!mesh) throw std::invalid_argument("mesh obstacle is null");
  meshes_.push_back(std::move(mesh));
}

void Colliders::advance(double h, const Vec3& gravity, double decay) {
  for (SphereCollider& s : spheres_) {
    if (s.isDynamic()) {
      s.velocity = decay * s.velocity + h * gravity;
      s.angular_velocity *= decay;
    }
    s.center += h * s.velocity;
  }
}

int depenetrateStart(const Colliders& colliders, const std::vector<char>& movable,
                     Points& positions, Points* previous_positions) {
  const GroundPlane& ground = colliders.ground();
  const std::vector<SphereCollider>& spheres = colliders.spheres();
  const SphereCandidates candidates(spheres, 0.0);  // the spheres where they stand
  int moved = 0;
  for (Eigen::Index i = 0; i < positions.cols(); ++i) {
    if (!movable[i]) continue;
    const Vec3 before = positions.col(i);
    candidates.forEach(before, before, [&](std::size_t k) {
      const SphereCollider& s = spheres[k];
      if (s.isDynamic()) return;
      const Vec3 d = positions.col(i) - s.center;
      const double dist = d.norm();
      if (dist >= s.radius) return;
      const Vec3 out = dist > 1e-12 ? Vec3(d / dist) : Vec3::UnitZ();
      positions.col(i) = s.center + s.radius * out;
    });
    if (ground.enabled) positions(2, i) = std::max(positions(2, i), ground.height);
    if (positions.col(i) == before) continue;
    if (previous_positions != nullptr) previous_positions->col(i) += positions.col(i) - before;
    ++moved;
  }
  return moved;
}

int resolveCollisions(const CollisionStep& step, Colliders& colliders, Points& end,
                      Points& velocities, bool in_solve_contacts) {
  const GroundPlane& ground = colliders.ground();
  std::vector<SphereCollider>& spheres = colliders.mutableSpheres();
  std::vector<SphereReaction> reactions(spheres.size());
  const SphereCandidates candidates(spheres, step.h);
  int corrected = 0;
  for (Eigen::Index i = 0; i < end.cols(); ++i) {
    if (!step.movable[i]) continue;
    const Vec3 solved = end.col(i);
    // The solve already applied the ground's and the meshes' friction with their contact
    // forces (ContactForces): what is left here is a small residual, corrected without any.
    const std::optional<Vec3> still_motion =
        in_solve_contacts ? std::optional<Vec3>(Vec3::Zero()) : step.freeMotion(i);
    Vec3 normal = Vec3::Zero();
    bool hit =
        collideWithSpheres(step, spheres, candidates, in_solve_contacts, i, end, reactions, normal);
    // The ground before the meshes: lifting a particle onto the ground must not put it into
    // an obstacle standing there (a table leg); the mesh response keeps its start side.
    hit = collideWithGround(step, ground, still_motion, i, end, normal) || hit;
    hit = collideWithMeshes(step, colliders.meshes(), still_motion, i, end, normal) || hit;
    // The bodies were not in the solve: their friction presses with the particle's own load.
    hit = collideWithBodyColliders(step, colliders.bodies(), i, end) || hit;
    // A mesh standing on the ground may push a particle round its bottom edge below it.
    if (ground.enabled) end(2, i) = std::max(end(2, i), ground.height);
    if (hit) {
      restartAlong(step, normal, i, solved, end.col(i), velocities);
      ++corrected;
    }
  }
  applySphereReactions(step, reactions, in_solve_contacts, spheres, end, velocities);
  return corrected;
}

}  // namespace cloth_sim
