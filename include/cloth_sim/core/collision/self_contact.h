/// @file self_contact.h
/// Contact of a cloth with itself (docs/method.md, "Self-contact"): the scene's option and the
/// one object Simulation calls in each substep, which runs one of two modes:
///
/// - `triangles` (the default): vertex-triangle and edge-edge contact at the thickness, with
///   continuous detection of every impact and the untangling of a cloth that already crosses
///   itself (TriangleSelfContact); any thickness at any resolution.
/// - `particles`: particle-particle contact with a displacement bound (ParticleSelfContact);
///   cheaper, but only for a thickness of about the particle spacing, which it checks.
#pragma once

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "cloth_sim/core/collision/colliders.h"
#include "cloth_sim/core/collision/particle_self_contact.h"
#include "cloth_sim/core/collision/triangle_self_contact.h"
#include "cloth_sim/core/linalg/types.h"

namespace cloth_sim {

/// Which primitives of the cloth touch (SelfContactSettings::mode).
enum class SelfContactMode { kTriangles, kParticles };
/// "triangles", "particles".
const char* selfContactModeName(SelfContactMode mode);
/// The mode named @p name; throws std::invalid_argument "self_collision.mode '<name>' must be
/// one of triangles, particles".
SelfContactMode selfContactModeFromName(const std::string& name);

/// Thickness (m) of mode triangles when the scene gives none: a cloth's real thickness is 0.3 to
/// 3 mm (the mean rest edge instead, when that is shorter).
inline constexpr double kAutomaticThickness = 0.002;
/// The thinnest thickness (m) mode triangles keeps: measured on a pile of strips, 0.1 mm has no
/// intersecting pair at any substep; at 10 um some contacts pressed by the ground come within
/// rounding of touching and cross (untangled within the frame), at 1 um crossings are left at
/// the end of frames (docs/method.md, "Self-contact").
inline constexpr double kMinimumThickness = 1e-4;

/// The scene's self_collision option (docs/scene_format.md). Off unless a scene asks.
struct SelfContactSettings {
  bool enabled = false;
  SelfContactMode mode = SelfContactMode::kTriangles;
  /// Distance t (m) the cloth keeps from itself: between the mid-surfaces of two layers (the
  /// cloth's thickness) in mode triangles, between two particles in mode particles
  /// (settings::kSelfThickness). 0 = automatic: kAutomaticThickness (or the mean rest edge
  /// length when shorter) in mode triangles, the mean rest edge length in mode particles. Mode
  /// triangles refuses a t below kMinimumThickness, mode particles one below
  /// ParticleSelfContact::minimumThickness.
  double thickness = 0.0;
  /// Coulomb coefficient mu of cloth on cloth (settings::kSelfFriction): the tangential slide of
  /// two primitives in contact is cut by mu times the normal correction.
  double friction = 0.3;

  /// Throws std::invalid_argument with the table's refusal, "self_collision.<field> <value> must
  /// be <rule>" (Setting::refusal).
  void validate() const;
};

/// The self-contact of one cloth in the mode of its settings. Simulation::substep calls
/// limitDisplacement before the colliders' projection and resolve after it.
class SelfContact {
 public:
  /// @p triangles: the cloth's triangles; @p rest: rest positions (m), which give the
  /// automatic thickness and the rest distance of each pair. Throws std::invalid_argument
  /// naming the field for bad settings or a thickness the mode cannot keep.
  SelfContact(const Eigen::Matrix3Xi& triangles, const Points& rest,
              const SelfContactSettings& settings);
  ~SelfContact();
  /// A deep copy, with the state carried from one substep to the next (the pair list):
  /// snapshots keep one, so that a restored run lists the same pairs as the run it left.
  SelfContact(const SelfContact& other);
  SelfContact(SelfContact&&) noexcept;
  SelfContact& operator=(SelfContact&&) noexcept;

  SelfContactMode mode() const { return mode_; }
  /// The thickness t in use (m): the setting, or the automatic one (SelfContactSettings).
  double thickness() const { return thickness_; }
  double friction() const { return friction_; }
  /// Largest displacement (m) of a particle in one substep: 0.3 t in mode particles, unbounded
  /// (infinity) in mode triangles, whose impacts are detected continuously.
  double maxDisplacement() const;

  /// Mode particles: the displacement bound (ParticleSelfContact::limitDisplacement). Mode
  /// triangles: nothing (returns 0).
  int limitDisplacement(const CollisionStep& step, Points& end, Points& velocities);
  /// The contact response of the substep; @p ground is clamped where the mode pushes particles.
  /// Returns the particles moved.
  int resolve(const CollisionStep& step, const GroundPlane& ground, Points& end,
              Points& velocities);

  /// Mode particles: the pairs (i < j) of non-neighbour particles closer than their contact
  /// distance at @p positions (for tests); empty in mode triangles.
  std::vector<std::pair<int, int>> contacts(const Points& positions);
  /// Mode particles: how many times resolve rebuilt its pair list; 0 in mode triangles.
  long rebuilds() const;
  /// The triangle mode's object (its statistics), or null in mode particles.
  TriangleSelfContact* triangles() { return triangles_.get(); }
  const TriangleSelfContact* triangles() const { return triangles_.get(); }
  /// Thread CPU time (s) spent in limitDisplacement and resolve since construction (the
  /// benchmark's measure: not inflated when other processes share the core).
  double cpuSeconds() const { return cpu_seconds_; }
  /// Threads of the searches (mode particles: the pair search; mode triangles: the
  /// intersection check of tangles), in fixed blocks: the same pairs in the same order for any
  /// count.
  void setThreads(int threads);

 private:
  SelfContactMode mode_;
  double thickness_ = 0.0;
  double friction_ = 0.0;
  std::unique_ptr<ParticleSelfContact> particles_;
  std::unique_ptr<TriangleSelfContact> triangles_;
  double cpu_seconds_ = 0.0;
};

/// Thread CPU time (s) of the calling thread (CLOCK_THREAD_CPUTIME_ID).
double threadCpuSeconds();

}  // namespace cloth_sim
