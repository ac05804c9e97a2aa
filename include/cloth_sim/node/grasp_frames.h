/// @file grasp_frames.h
/// The tf2 side of grasps: where each grasp's frame is at a simulated time.
#pragma once

#include <map>
#include <string>
#include <vector>

#include <geometry_msgs/TransformStamped.h>
#include <tf2/buffer_core.h>

#include "cloth_sim/core/simulation/grasp.h"

namespace cloth_sim::node {

/// A transform tf2 gave for a stamp, and whether the stamp was outside what it holds.
struct FrameSample {
  geometry_msgs::TransformStamped transform;
  /// The stamp is before the buffer's oldest transform (dropped past ~tf_buffer_duration, or
  /// never published): the oldest one was given, never a later one.
  bool before_buffer = false;
  /// The stamp is after the newest transform: the newest was given (held).
  bool after_buffer = false;
};

/// @p frame in @p target at @p stamp: interpolated by tf2 when the buffer covers the stamp; the
/// oldest transform before it, the newest after it. Throws tf2::TransformException when the
/// frames are not connected.
FrameSample sampleFrame(const tf2::BufferCore& buffer, const std::string& target,
                        const std::string& frame, const ros::Time& stamp);

/// Looks grasp frames up in a tf2 buffer it does not own, for Simulation's GraspPoseSource.
///
/// A grasp frame is a tf frame moved by a fixed offset (m, in that frame). At each substep the
/// node asks for its pose at the substep's stamp: tf2 interpolates between the two transforms
/// around it. When the buffer has nothing that recent (the frame's publisher is behind or has
/// stopped), the latest transform is held; once it is older than the timeout the frame is
/// stale (reported in cloth/state and /diagnostics). A stamp before the buffer's oldest
/// transform (a trajectory published further ahead than ~tf_buffer_duration) holds the oldest
/// one and says so (Tracked::before_buffer): never a later pose. A frame that cannot be looked up at all any
/// more (its tree was cut) keeps its last pose and is stale too.
class GraspFrames {
 public:
  /// @p sim_frame: ~frame_id; @p timeout (s, > 0): age of the latest transform, against the
  /// stamp asked, beyond which a frame counts as stale.
  GraspFrames(const tf2::BufferCore& buffer, std::string sim_frame, double timeout);

  /// The pose (in sim_frame) of @p frame moved by @p offset at @p stamp (sampleFrame: the
  /// oldest before the buffer, the latest after it). Throws std::invalid_argument naming the frame when it is
  /// unknown or cannot be transformed into sim_frame, or when @p offset is not finite.
  Pose lookup(const std::string& frame, const Vec3& offset, const ros::Time& stamp) const;

  /// Tracks grasp @p id on @p frame with @p offset, now at @p pose (@p seen false: not looked
  /// up yet; pose is a placeholder).
  void add(int id, const std::string& frame, const Vec3& offset, const Pose& pose,
           bool seen = true);
  void remove(int id);
  void clear() { grasps_.clear(); }

  /// Grasp @p id's pose at @p stamp (see the class comment); an unknown id gives the identity.
  Pose poseAt(int id, const ros::Time& stamp);

  /// What the node reports about one tracked grasp.
  struct Tracked {
    std::string frame;
    Vec3 offset = Vec3::Zero();
    Pose last_pose = Pose::Identity();
    bool stale = false;
    bool before_buffer = false;  ///< the last lookup was before the buffer's oldest transform
    bool seen = true;  ///< tf2 has given this frame once (false for a body not placed yet)
  };
  /// The grasp @p id, or nullptr.
  const Tracked* find(int id) const;
  /// Every tracked frame (to keep and restore with a snapshot).
  const std::map<int, Tracked>& all() const { return grasps_; }
  void restore(std::map<int, Tracked> tracked) { grasps_ = std::move(tracked); }
  /// Frames of the stale grasps, "frame (grasp id)".
  std::vector<std::string> staleFrames() const;

 private:
  const tf2::BufferCore& buffer_;
  std::string sim_frame_;
  double timeout_;
  std::map<int, Tracked> grasps_;
};

}  // namespace cloth_sim::node
