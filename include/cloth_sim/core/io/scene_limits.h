/// @file scene_limits.h
/// What a simulation built from a scene can follow: bounds on pin targets and spheres derived
/// from the cloth itself, so that an input the simulation could only answer by diverging is
/// refused with its rule instead of being accepted (docs/ros_interface.md, "Bad input").
#pragma once

#include <string>
#include <vector>

#include "cloth_sim/core/collision/colliders.h"
#include "cloth_sim/core/linalg/types.h"
#include "cloth_sim/core/model/pins.h"

namespace cloth_sim {

class Simulation;

/// The reach used when none is given: the node's default ~sphere_cull_distance (m).
inline constexpr double kDefaultReach = 20.0;

/// Bounds derived from a cloth's initial state. Each check throws std::invalid_argument
/// "<what> ... must ..." naming the value and the rule; @p what names the input (a scene field
/// such as "colliders.spheres[0]", or "sphere", "target"; checkSphere's may be empty).
struct SceneLimits {
  Vec3 center = Vec3::Zero();  ///< m, mean of the cloth's initial positions
  double size = 1.0;           ///< m, largest side of their bounding box (the cloth's size)
  double cloth_mass = 1.0;     ///< kg, total mass of the cloth
  double reach = kDefaultReach;  ///< m, nothing may be put farther than this from center

  /// The heaviest ball allowed, as a multiple of the cloth's mass: a far heavier ball falls
  /// through any cloth, stretching it beyond the divergence limit.
  static constexpr double kMaxBallToCloth = 100.0;
  /// The lightest dynamic ball, as a multiple of the cloth's mass: one far lighter (5e-324 kg)
  /// gets an infinite inverse mass in the contact impulses.
  static constexpr double kMinBallToCloth = 1e-9;

  /// How far a pin's target may be from center, in cloth sizes: two pins can then be at most
  /// 3 sizes apart, a stretch the cloth follows without diverging (a target 5 m below a 1 m
  /// cloth, within the 20 m reach, looped automatic resets every 0.5 s).
  static constexpr double kPinReachSizes = 1.5;
  /// How fast a pin's target moves towards where it was sent, in cloth sizes per second (2 m/s
  /// on a 1 m cloth; a 1.5 m jump in one frame gave a 3990 % strain spike).
  static constexpr double kPinSpeedSizes = 2.0;

  /// The limits of @p sim's initial cloth, with @p reach (m, > 0).
  static SceneLimits of(const Simulation& sim, double reach = kDefaultReach);

  /// @p point (m) must lie within reach of center.
  void checkPoint(const std::string& what, const Vec3& point) const;
  /// A pin target @p point (m): checkPoint, and within kPinReachSizes of the cloth's size of
  /// center.
  void checkPinTarget(const std::string& what, const Vec3& point) const;
  /// m/s, the speed a pin's target is followed at (Simulation::setPinSpeedLimit).
  double pinSpeed() const { return kPinSpeedSizes * size; }
  /// The sphere's centre within reach; its radius at most the cloth's size (a larger sphere
  /// around the cloth flings every particle to its surface); its mass 0 or between
  /// kMinBallToCloth and kMaxBallToCloth times the cloth's; its speed at most its radius per implicit step @p substep (s): faster,
  /// it crosses the cloth between two contact resolutions.
  void checkSphere(const std::string& what, const SphereCollider& sphere, double substep) const;
  /// @p sphere must not hold a hard-pinned particle of @p pins (at @p positions, m) or a pin
  /// target inside it: the pinned particles skip collisions, so the cloth around them would be
  /// stuck across the sphere's surface (a 1 m sphere around the hanging cloth: 830 % strain for
  /// as long as it stays).
  static void checkSphereAroundPins(const std::string& what, const SphereCollider& sphere,
                                    const std::vector<Pin>& pins, const Points& positions);
};

}  // namespace cloth_sim
