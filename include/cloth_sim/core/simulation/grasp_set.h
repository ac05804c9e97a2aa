/// @file grasp_set.h
/// The grasps of one simulation: made, released, placed at their frames, and what they carry.
#pragma once

#include <utility>
#include <vector>

#include "cloth_sim/core/linalg/types.h"
#include "cloth_sim/core/model/pins.h"
#include "cloth_sim/core/simulation/grasp.h"

namespace cloth_sim {

/// Every grasp of a simulation, in the order they were made, and the pose source that moves
/// them. A grasp's particles are hard pins of the simulation's PinSet, which every call that
/// changes them is given; the set keeps which pins are whose.
class GraspSet {
 public:
  /// Holds @p vertices (distinct, in [0, positions.cols()), not pinned in @p pins yet, at least
  /// one) rigidly by a frame now at @p pose: each becomes a hard pin of @p pins at its position
  /// in @p positions (m). Returns the grasp id. Throws std::invalid_argument naming what is
  /// wrong, with @p pins untouched.
  int add(const std::vector<int>& vertices, const Pose& pose, const Points& positions,
          PinSet& pins);
  /// Lets go of grasp @p id: its pins are removed from @p pins. Throws std::invalid_argument
  /// for an unknown id.
  void remove(int id, PinSet& pins);
  /// Drops every grasp (their pins are the caller's to reset); ids keep counting up.
  void clear() { grasps_.clear(); }

  /// The grasp holding pin @p pin_id, or nullptr for a pin of the user's own.
  const Grasp* graspOf(int pin_id) const;
  /// The grasp with @p id, or nullptr.
  const Grasp* find(int id) const;
  /// Throws std::invalid_argument if pin @p pin_id belongs to a grasp (@p what: "removed",
  /// "moved"): a grasp's pins follow its frame only.
  void requireNotGrasped(int pin_id, const char* what) const;

  /// The function asked, at each substep, where each grasp's frame is (empty: frames stay put).
  void setPoseSource(GraspPoseSource source) { pose_source_ = std::move(source); }
  /// The pose source set by setPoseSource (empty if none).
  const GraspPoseSource& poseSource() const { return pose_source_; }
  /// Each grasp's frame at simulated time @p time (s), from the pose source (an answer that is
  /// not finite keeps the last one); its pose moved rigidly towards the frame, no held particle
  /// moving more than @p max_move m (the frame itself when none would), and its pins' targets
  /// there, written into @p pins and, if given, @p pins_at (the substep's copy of the pins).
  /// With @p pushes (3 x N, N: the cloth's self-contact pushing each particle,
  /// ContactForces::addSelfPushes; empty: none), a pose whose move points into the sum of its
  /// held particles' pushes keeps its place (it turns still): a gripper set down on a stack of
  /// cloth stops on it (FrameInputs::pinsAt says why); its lag shows how far it stays behind.
  void place(double time, double max_move, PinSet& pins, PinSet* pins_at,
             const Points& pushes = Points());
  /// Each grasp's wrench from the pin loads @p loads (N, in pins.pins() order) at @p positions
  /// (m): the force sum and its torque about its pose's origin.
  void updateWrenches(const PinSet& pins, const std::vector<Vec3>& loads, const Points& positions);

  const std::vector<Grasp>& grasps() const { return grasps_; }
  bool empty() const { return grasps_.empty(); }

 private:
  std::vector<Grasp> grasps_;
  int next_id_ = 0;
  GraspPoseSource pose_source_;
};

}  // namespace cloth_sim
