/// @file colliders.h
/// Kinematic colliders (spheres, ground plane) and the contact response applied after a solve.
#pragma once

#include <memory>
#include <optional>
#include <vector>

#include "cloth_sim/core/collision/body_collider.h"
#include "cloth_sim/core/collision/mesh_obstacle.h"
#include "cloth_sim/core/linalg/types.h"

namespace cloth_sim {

/// A sphere the cloth collides with.
///
/// With mass 0 it is kinematic: the user places it and may give it a constant velocity (thrown);
/// nothing pushes it back. With mass > 0 it is a rigid body (solid ball, moment of inertia
/// 2/5 m r^2) under gravity: cloth particles, the ground and other spheres push on it with equal
/// and opposite impulses, so momentum is exchanged consistently.
struct SphereCollider {
  int id = -1;                  ///< stable handle, unique within Colliders
  Vec3 center = Vec3::Zero();   ///< m
  double radius = 0.1;          ///< m, > 0
  Vec3 velocity = Vec3::Zero(); ///< m/s; a kinematic sphere keeps it, a dynamic one starts with it
  /// Coulomb friction coefficient mu >= 0 of its contacts (with the cloth: the tangential slide
  /// is cut by mu times the normal correction; with the ground and other spheres: the tangential
  /// impulse is at most mu times the normal impulse). 0 = frictionless.
  double friction = 0.0;
  double mass = 0.0;            ///< kg, >= 0; 0 = kinematic
  Vec3 angular_velocity = Vec3::Zero();  ///< rad/s (dynamic spheres spin under friction)
  /// Normal restitution e in [0, 1] of its impacts with the ground and other spheres: the normal
  /// relative speed after an impact is e times the one before (0 = no bounce).
  double restitution = 0.0;

  bool isDynamic() const { return mass > 0.0; }
  /// Moment of inertia of a solid ball, 2/5 m r^2 (kg m^2).
  double inertia() const { return 0.4 * mass * radius * radius; }
};

/// The plane z = height with normal +z.
struct GroundPlane {
  bool enabled = false;
  double height = 0.0;    ///< m
  double friction = 0.0;  ///< Coulomb coefficient mu >= 0
};

/// The colliders of a simulation, with stable sphere ids.
class Colliders {
 public:
  /// Adds a sphere (its id field is ignored) and returns the new id. Throws
  /// std::invalid_argument naming the bad field (non-finite, radius <= 0, friction < 0).
  int addSphere(const SphereCollider& sphere);
  /// Throws std::invalid_argument if no sphere has this id.
  void removeSphere(int id);
  /// Places sphere @p id at @p center with @p velocity; validated as in addSphere.
  void moveSphere(int id, const Vec3& center, const Vec3& velocity);
  const SphereCollider* findSphere(int id) const;
  const std::vector<SphereCollider>& spheres() const { return spheres_; }
  /// Mutable access for the contact response (ids must not be changed).
  std::vector<SphereCollider>& mutableSpheres() { return spheres_; }

  /// Throws std::invalid_argument when height or friction is not finite or friction < 0.
  void setGround(const GroundPlane& ground);
  const GroundPlane& ground() const { return ground_; }

  /// Adds a static mesh obstacle (shared, immutable: copying Colliders stays cheap).
  void addMesh(std::shared_ptr<const MeshObstacle> mesh);
  const std::vector<std::shared_ptr<const MeshObstacle>>& meshes() const { return meshes_; }

  /// The rigid bodies (spheres, capsules, boxes, meshes; still or on a moving frame).
  const BodySet& bodies() const { return bodies_; }
  /// The same, to add, remove, move or place bodies (Simulation's body edits go through it).
  BodySet& mutableBodies() { return bodies_; }

  /// Moves the spheres over one step: a kinematic one by velocity * h; a dynamic one by
  /// symplectic Euler under @p gravity and the model's drag (v <- @p decay v + g h, spin
  /// <- decay spin, then centre += v h), decay = exp(-damping h) as for the cloth.
  void advance(double h, const Vec3& gravity = Vec3::Zero(), double decay = 1.0);
  bool empty() const {
    return spheres_.empty() && meshes_.empty() && bodies_.empty() && !ground_.enabled;
  }

 private:
  std::vector<SphereCollider> spheres_;
  std::vector<std::shared_ptr<const MeshObstacle>> meshes_;
  GroundPlane ground_;
  BodySet bodies_;
  int next_id_ = 0;
};

/// What the collision response of one step reads besides the colliders, built once per step
/// by Simulation (the references must outlive the step).
struct CollisionStep {
  double h;                          ///< time step (s)
  const Eigen::VectorXd& mass;       ///< per particle (kg)
  const std::vector<char>& movable;  ///< false for hard-pinned particles: never pushed
  const Points& start;               ///< positions at the start of the step (m)
  /// Velocities at the start of the step (m/s), or null. With them (and gravity) friction
  /// presses with the particle's own load only (frictionLoad); without, with the whole
  /// normal correction.
  const Points* velocities = nullptr;
  Vec3 gravity = Vec3::Zero();       ///< m/s^2, with velocities
  /// s, the implicit step h_i of the step's integrator (StepRecurrence): its end velocity
  /// changes by 1 / h_i per metre its end position moves (implicit Euler h, BDF2 2h/3, implicit
  /// midpoint h/2), so a correction after the solve keeps the velocity the integrator's own.
  /// 0: h.
  double implicit_h = 0.0;
  /// 1 / h_i (1/s): the velocity change per unit of end-position correction.
  double velocityGain() const { return 1.0 / (implicit_h > 0.0 ? implicit_h : h); }
  /// The state's v_n (State::previous_velocities) of a multistep integrator (BDF2), or null: a
  /// contact restarts it along its normal (see resolveCollisions).
  Points* history_velocities = nullptr;
  /// Displacement (m) particle @p i would make over the step without internal or contact
  /// forces, h v + h^2 g; null without velocities.
  std::optional<Vec3> freeMotion(Eigen::Index i) const {
    if (velocities == nullptr) return std::nullopt;
    return Vec3(h * velocities->col(i) + h * h * gravity);
  }
};

/// Moves the movable particles that start a step inside a kinematic sphere or below the
/// ground onto its surface, and their history (@p previous_positions, or null) by the same
/// amount, so the correction carries no velocity. A particle is inside at the start only when
/// the cloth was placed there (a scene that starts overlapping, a sphere or the ground moved
/// onto the cloth between frames) or when a solve left a residual: that overlap is not a
/// motion of the step. Pushed out in the step instead, it would become the velocity
/// depth / h, so the energy a cloth gets from starting 15 cm inside a sphere would grow as
/// 1 / h^2 (1 substep of 1/60 s: 3.6 J; 512 substeps: 34,600 J and a strain of 15) and no step
/// size would converge. Dynamic spheres keep their overlap to the solve, which exchanges its
/// momentum; meshes and bodies keep the side a particle starts on. Spheres at their start
/// centres (before Colliders::advance). Returns the number of particles moved.
int depenetrateStart(const Colliders& colliders, const std::vector<char>& movable,
                     Points& positions, Points* previous_positions);

/// Contact response after the solve (Liu et al. 2013, section 5: move penetrating particles out).
///
/// For each movable particle (CollisionStep::movable): spheres are tested along the particle's
/// path relative to the sphere (from start - old centre to end - new centre), so a fast sphere
/// cannot pass through a particle within one step; a particle that entered is put back on the
/// surface where it entered; mesh obstacles keep it on the side it came from (MeshObstacle);
/// one below the ground is lifted onto it (the ground before the meshes, and a particle is
/// clamped to the ground after them). Coulomb friction cuts the tangential displacement
/// relative to the collider (for a spinning sphere: relative to its moving surface) by mu times
/// the normal correction (sticking when it is smaller), the normal correction counted only up
/// to the particle's own load when CollisionStep::velocities is given (frictionLoad: a spring
/// pulling a particle into a box's side face or round a ball must not glue it there); with
/// @p in_solve_contacts the ground and the meshes correct without friction (the solve applied
/// it with the contact forces). Each corrected particle gets the
/// velocity (end - start) / h, so velocities stay consistent with the projected positions:
/// against a still collider the normal speed into it becomes 0 and no energy is added.
///
/// Against a dynamic sphere of mass M the correction d of a particle of mass m is shared: the
/// particle moves by M/(M+m) d and the sphere receives the opposite impulse (its centre moves by
/// -m/(M+m) d; its velocity and spin change accordingly), so linear momentum is conserved
/// exactly. Sphere reactions are summed over all particles and applied at the end.
///
/// Spheres are at their end-of-step centres (Colliders::advance done); the start centre is
/// center - velocity * h. With @p in_solve_contacts the solver already solved the contacts
/// (ContactForces): a particle overlapping a dynamic sphere by less than 5 % of its radius is
/// then left alone. Returns the number of corrected particles.
int resolveCollisions(const CollisionStep& step, Colliders& colliders, Points& end,
                      Points& velocities, bool in_solve_contacts = false);

}  // namespace cloth_sim
