/// @file sim_clock.h
/// Simulated time as ROS time (what /clock publishes with ~publish_clock), and a digest of a
/// state to compare runs bit for bit.
#pragma once

#include <string>

#include <ros/time.h>

#include "cloth_sim/core/model/model.h"

namespace cloth_sim::node {

/// Maps the core's simulated time (State::time, s, back to 0 at every reset) to ROS stamps that
/// never go back: stamp(t) = origin + t, and a reset moves the origin to the stamp it reached,
/// so tf2 buffers (which clear on a jump back in time) and /clock listeners see one timeline.
class SimClock {
 public:
  /// @p origin: the ROS time of simulated time 0 (1 s with ~publish_clock, else the ROS time at
  /// start).
  explicit SimClock(ros::Time origin = ros::Time()) : origin_(origin) {}

  /// The ROS time of simulated time @p sim_time (s, >= 0).
  ros::Time stamp(double sim_time) const { return origin_ + ros::Duration(sim_time); }
  /// The simulation restarts at 0 from @p sim_time: the stamps go on from stamp(sim_time).
  void restart(double sim_time) { origin_ = stamp(sim_time); }
  /// The simulation jumps from simulated time @p from to @p to (s, a restored snapshot or a
  /// state set): the stamps go on from stamp(@p from), never back; if @p to is later than that
  /// stamp itself, they jump forward to @p to (an origin before ROS time 0 does not exist).
  void jump(double from, double to) {
    const ros::Time reached = stamp(from);
    origin_ = reached.toSec() >= to ? reached - ros::Duration(to) : ros::Time(0, 0);
  }
  /// Without /clock of its own the node follows the ROS time: before each frame it anchors the
  /// frame's end, simulated time @p sim_time, at @p now, so the substeps are looked up over the
  /// frame just past (which the tf2 buffer has) and every output of the frame is stamped now.
  void anchor(const ros::Time& now, double sim_time) { origin_ = now - ros::Duration(sim_time); }
  ros::Time origin() const { return origin_; }

 private:
  ros::Time origin_;
};

/// FNV-1a (64 bit) of the bytes of every position and velocity and of the time, as 16 hex
/// digits: two states with the same digest are (but for a hash collision) bit-identical.
std::string stateDigest(const State& state);

}  // namespace cloth_sim::node
