/// @file frame_inputs.h
/// What moves during a frame and where it is at substep k: the user's pin moves, the grasps'
/// frames and the kinematic spheres' jumps, spread over the frame's substeps.
#pragma once

#include <utility>
#include <vector>

#include "cloth_sim/core/collision/colliders.h"
#include "cloth_sim/core/linalg/types.h"
#include "cloth_sim/core/model/pins.h"
#include "cloth_sim/core/simulation/grasp_set.h"

namespace cloth_sim {

/// The inputs of a frame, spread over its n substeps so that nothing jumps in the first one
/// (a pin yanked in one implicit step stretches its springs by the whole move):
///
/// - pin paths: a pin target the user moved since the last frame moves there linearly, at the
///   fraction k / n of its way at substep k, and at most a speed limit per frame (a farther
///   target is reached over several frames);
/// - grasp targets: before each substep each grasp's frame is asked where it is at the
///   substep's end time (GraspSet::place), so a moving gripper carries the cloth continuously;
///   its held particles follow the frame at the same speed limit, the substep's share of it (a
///   frame that jumps is caught up with over several frames);
/// - kinematic sphere jumps: a kinematic sphere the user moved gets the move as an extra
///   velocity for the frame, so it sweeps there across the substeps.
///
/// It works on the simulation's PinSet and Colliders, which each call is given.
class FrameInputs {
 public:
  /// Every pin's target starts at its particle's position in @p positions (m): a target away
  /// from it is then approached at the speed limit instead of in one jerk (start, resets).
  void startPinsAt(const PinSet& pins, const Points& positions);
  /// Pin @p id, just added: its target is approached from @p position (m), its particle.
  void addPin(int id, const Vec3& position) { frame_targets_.emplace_back(id, position); }
  /// Sets sphere @p id of @p colliders to @p center (m) and @p velocity (m/s). A dynamic ball is
  /// placed at once; a kinematic sphere keeps its centre and goes there across the next frame's
  /// substeps. Throws std::invalid_argument as Colliders::moveSphere does, changing nothing.
  void moveSphere(Colliders& colliders, int id, const Vec3& center, const Vec3& velocity);
  /// Forgets the sphere moves not yet made (resets).
  void clearSphereJumps() { sphere_jumps_.clear(); }

  /// Starts a frame of @p frame_time s at the user's @p pins: each pin whose target moved since
  /// the last frame gets its path, from where its target stood when the last frame ended to the
  /// new target or @p max_pin_move m (> 0) of the way there (the grasps' held particles move at
  /// most as far in the frame); each pending sphere jump becomes an extra velocity of its sphere
  /// in @p colliders.
  void beginFrame(const PinSet& pins, double max_pin_move, double frame_time, Colliders& colliders);
  /// The pins substep @p k (1..n) of @p n solves with: @p pins itself when no target moved this
  /// frame, else a copy with each moved target at the fraction k / n of its path. Each grasp of
  /// @p grasps is placed first towards its frame's pose at time @p time (s, the substep's end)
  /// in @p pins and the copy, its held particles moving at most (k - j) / n of the frame's
  /// max_pin_move since substep j, the one placed before (a k past j + 1: merged substeps).
  /// A hard pin whose particle the cloth's self-contact pushes (@p pushes, 3 x N, N, as
  /// ContactForces::addSelfPushes; empty: none) drops the part of the rest of its path that
  /// would drive its particle into that contact, and goes on along what is left: it stops where
  /// it touches, as a gripper set down on a stack does, and its target is approached again in
  /// later frames as far as the contact lets it. Driven on, it squeezed the layers under it
  /// against the ground, which no position satisfies, and they were pushed out sideways (the
  /// fold under error control: 0.04 J to 12 J in a frame, docs/benchmark.md). A grasp stops
  /// likewise (GraspSet::place). Only the pairs in the solve push, not the proximity stage
  /// after it.
  const PinSet& pinsAt(int k, int n, double time, GraspSet& grasps, PinSet& pins,
                       const Points& pushes = Points());
  /// Ends the frame. If it was @p kept, the sphere jumps' velocities are taken back out;
  /// otherwise (rolled back, @p colliders restored) the moved spheres are put where they were
  /// sent. Each target's place at this frame's end is kept for the next (a grasped pin's where
  /// its frame put it, read from @p pins).
  void endFrame(bool kept, const PinSet& pins, const GraspSet& grasps, double frame_time,
                Colliders& colliders);

  /// A pin's target this frame: from where it stood at the end of the last frame to where it
  /// stands at the end of this one (m).
  struct PinPath {
    int id;
    Vec3 from, to;
  };
  /// The pins that move this frame (between beginFrame and endFrame).
  const std::vector<PinPath>& paths() const { return paths_; }

 private:
  /// A kinematic sphere the user moved since the last frame.
  struct SphereJump {
    int id;
    Vec3 displacement;  ///< m, spread over the frame's substeps
  };
  /// Shortens the paths of the hard pins pushed by @p pushes (pinsAt) after @p done of @p n
  /// substeps.
  void stopAtContacts(int done, int n, const Points& pushes);
  /// Adds @p sign (+1, -1) times each jump over @p frame_time to its sphere's velocity.
  void applySphereJumps(double sign, double frame_time, Colliders& colliders) const;

  std::vector<std::pair<int, Vec3>> frame_targets_;  ///< pin id -> target at the last frame's end
  std::vector<std::pair<int, Vec3>> frame_end_;      ///< pin id -> target at this frame's end
  std::vector<PinPath> paths_;
  double max_pin_move_ = 0.0;  ///< m, this frame's (beginFrame)
  int placed_substeps_ = 0;    ///< of this frame, whose grasps are placed (pinsAt)
  PinSet pins_at_;  ///< the substep's pins when some target moves this frame
  std::vector<SphereJump> sphere_jumps_;
};

}  // namespace cloth_sim
