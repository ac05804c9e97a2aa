#include "cloth_sim/core/colliders.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "cloth_sim/core/contact_response.h"

namespace cloth_sim {
namespace {

void checkSphere(const Vec3& center, double radius, const Vec3& velocity, double friction) {
  if (!center.allFinite()) throw std::invalid_argument("sphere center must be finite");
  if (!velocity.allFinite()) throw std::invalid_argument("sphere velocity must be finite");
  if (!std::isfinite(radius) || radius <= 0.0) {
    throw std::invalid_argument("sphere radius " + std::to_string(radius) +
                                " m must be finite and > 0");
  }
  if (!std::isfinite(friction) || friction < 0.0) {
    throw std::invalid_argument("sphere friction " + std::to_string(friction) +
                                " must be finite and >= 0");
  }
}

/// Returns true and fixes @p rel_end (particle relative to the sphere centre at the end of the
/// step) if the relative path from @p rel_start entered the sphere.
bool collideSphere(const Vec3& rel_start, Vec3& rel_end, double radius, double mu) {
  const double r2 = radius * radius;
  const Vec3 path = rel_end - rel_start;
  Vec3 corrected;
  if (rel_start.squaredNorm() >= r2) {
    // Started outside: first crossing of the path with the sphere, if any (continuous test).
    const double a = path.squaredNorm(), b = rel_start.dot(path), c = rel_start.squaredNorm() - r2;
    const double disc = b * b - a * c;
    if (a <= 0.0 || disc < 0.0) return false;
    const double t = (-b - std::sqrt(disc)) / a;
    if (t < 0.0 || t > 1.0) return false;
    const Vec3 normal = (rel_start + t * path) / radius;
    // Keep the motion along the tangent plane at the entry point, drop the part into it.
    corrected = rel_end - std::min(0.0, (rel_end - (rel_start + t * path)).dot(normal)) * normal;
  } else {
    // Started inside (sphere spawned or teleported onto the cloth): push out radially.
    if (rel_end.squaredNorm() >= r2) return false;
    corrected = rel_end;
  }
  const double len = corrected.norm();
  const Vec3 normal = len > 1e-12 ? Vec3(corrected / len) : Vec3::UnitZ();
  corrected = radius * normal;  // on the surface
  const double normal_correction = (corrected - rel_end).norm();
  const Vec3 moved = applyFriction(corrected - rel_start, normal, normal_correction, mu);
  const Vec3 with_friction = rel_start + moved;
  const double with_len = with_friction.norm();
  rel_end = with_len > 1e-12 && with_len < radius ? Vec3(radius * with_friction / with_len)
                                                  : with_friction;
  return true;
}

}  // namespace

int Colliders::addSphere(const SphereCollider& sphere) {
  checkSphere(sphere.center, sphere.radius, sphere.velocity, sphere.friction);
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
  checkSphere(center, it->radius, velocity, it->friction);
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
  if (!std::isfinite(ground.friction) || ground.friction < 0.0) {
    throw std::invalid_argument("ground friction " + std::to_string(ground.friction) +
                                " must be finite and >= 0");
  }
  ground_ = ground;
}

void Colliders::addMesh(std::shared_ptr<const MeshObstacle> mesh) {
  if (!mesh) throw std::invalid_argument("mesh obstacle is null");
  meshes_.push_back(std::move(mesh));
}

void Colliders::advance(double h) {
  for (SphereCollider& s : spheres_) s.center += h * s.velocity;
}

int resolveCollisions(const Colliders& colliders, double h, const std::vector<char>& movable,
                      const Points& start, Points& end, Points& velocities) {
  int corrected = 0;
  const GroundPlane& ground = colliders.ground();
  for (Eigen::Index i = 0; i < end.cols(); ++i) {
    if (!movable[i]) continue;
    bool hit = false;
    for (const SphereCollider& s : colliders.spheres()) {
      const Vec3 old_center = s.center - h * s.velocity;
      Vec3 rel_end = end.col(i) - s.center;
      if (collideSphere(start.col(i) - old_center, rel_end, s.radius, s.friction)) {
        end.col(i) = s.center + rel_end;
        hit = true;
      }
    }
    for (const auto& mesh : colliders.meshes()) {
      Vec3 moved = end.col(i);
      if (mesh->collide(start.col(i), moved)) {
        end.col(i) = moved;
        hit = true;
      }
    }
    if (ground.enabled && end(2, i) < ground.height) {
      const double depth = ground.height - end(2, i);
      end(2, i) = ground.height;
      end.col(i) = start.col(i) +
                   applyFriction(end.col(i) - start.col(i), Vec3::UnitZ(), depth, ground.friction);
      end(2, i) = std::max(end(2, i), ground.height);
      hit = true;
    }
    if (hit) {
      velocities.col(i) = (end.col(i) - start.col(i)) / h;
      ++corrected;
    }
  }
  return corrected;
}

}  // namespace cloth_sim
