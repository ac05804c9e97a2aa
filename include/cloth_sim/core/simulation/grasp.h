/// @file grasp.h
/// A grasp: a set of hard pins whose targets follow one rigid frame (a gripper).
#pragma once

#include <functional>
#include <vector>

#include <Eigen/Geometry>

#include "cloth_sim/core/linalg/types.h"

namespace cloth_sim {

/// A rigid pose in the simulation frame: p_sim = rotation * p_local + translation (m).
using Pose = Eigen::Isometry3d;

/// Force (N) and torque (N m) about a point, both in the simulation frame.
struct Wrench {
  Vec3 force = Vec3::Zero();
  Vec3 torque = Vec3::Zero();
};

/// Particles held rigidly by a moving frame. Each held particle is a hard pin whose target is
/// pose * local: the particle keeps where it was in the frame when it was grasped. The pose
/// follows the frame at the pins' speed limit (Simulation::maxPinMove() per frame, rigidly): it
/// is the frame whenever the frame moves slower, and lags behind a frame that jumps (a yanked
/// gripper would throw the cloth through itself) until it has caught up.
struct Grasp {
  int id = -1;
  std::vector<int> pin_ids;   ///< one hard pin per held particle (Simulation::pins())
  std::vector<int> vertices;  ///< the held particles, in the order of pin_ids
  Points local;               ///< m, each held particle in the grasp frame (3 x held)
  /// Where the grasp holds its particles at the end of the last substep (or at grasp): the
  /// frame, or on the way to it when it moved faster than the speed limit (lag > 0).
  Pose pose = Pose::Identity();
  Pose frame = Pose::Identity();  ///< the frame's pose at the end of the last substep
  /// m, how far the farthest held particle is from where the frame would hold it (0: held on
  /// the frame).
  double lag = 0.0;
  /// The last placement kept the pose where it was: its move pointed into the cloth under it
  /// (GraspSet::place, self-contact pushing its held particles back).
  bool stopped = false;
  /// What the cloth exerts on the grasp after the last substep: the sum of its pins' loads
  /// (PinReactions) and their torque sum_i (x_i - origin) x load_i about pose's origin.
  Wrench wrench;
};

/// Where grasp @p grasp_id's frame is at simulated time @p time (s, State::time of the substep's
/// end), in the simulation frame. Simulation calls it once per grasp and substep, in order.
using GraspPoseSource = std::function<Pose(int grasp_id, double time)>;

}  // namespace cloth_sim
