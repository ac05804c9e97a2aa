#include "cloth_sim/node/grasp_frames.h"

#include <cstdlib>
#include <stdexcept>

#include <tf2/exceptions.h>
#include <tf2_eigen/tf2_eigen.h>

#include "cloth_sim/node/frame_resolver.h"

namespace cloth_sim::node {

FrameSample sampleFrame(const tf2::BufferCore& buffer, const std::string& target,
                        const std::string& frame, const ros::Time& stamp) {
  FrameSample out;
  try {
    out.transform = buffer.lookupTransform(target, frame, stamp);
    return out;
  } catch (const tf2::ExtrapolationException& e) {
    // tf2 says which end it fell off ("... into the past. Requested time T but the earliest
    // data is at time T0"): before the oldest sample, hold the oldest, never a later pose.
    const std::string what = e.what();
    const std::string marker = "earliest data is at time ";
    const std::size_t at = what.find(marker);
    if (what.find("into the past") != std::string::npos && at != std::string::npos) {
      const double oldest = std::strtod(what.c_str() + at + marker.size(), nullptr);
      if (oldest > 0.0) {
        out.transform = buffer.lookupTransform(target, frame, ros::Time(oldest));
        out.before_buffer = true;
        return out;
      }
    }
  }
  out.transform = buffer.lookupTransform(target, frame, ros::Time(0));  // the newest
  out.after_buffer = true;
  return out;
}

GraspFrames::GraspFrames(const tf2::BufferCore& buffer, std::string sim_frame, double timeout)
    : buffer_(buffer), sim_frame_(std::move(sim_frame)), timeout_(timeout) {}

Pose GraspFrames::lookup(const std::string& frame, const Vec3& offset,
                         const ros::Time& stamp) const {
  if (!offset.allFinite()) throw std::invalid_argument("offset is not finite");
  if (frame.empty()) throw std::invalid_argument("frame_id is empty: name the tf frame to follow");
  if (frame != sim_frame_ && !buffer_._frameExists(frame)) {
    throw std::invalid_argument("frame_id " + quotedName(frame) +
                                " is unknown to tf2 (no transform into '" + sim_frame_ +
                                "' has been published)");
  }
  geometry_msgs::TransformStamped t;
  try {
    t = sampleFrame(buffer_, sim_frame_, frame, stamp).transform;
  } catch (const tf2::TransformException& e) {
    throw std::invalid_argument("frame_id " + quotedName(frame) + " cannot be transformed into '" +
                                sim_frame_ + "': " + e.what());
  }
  return Pose(tf2::transformToEigen(t)) * Eigen::Translation3d(offset);
}

void GraspFrames::add(int id, const std::string& frame, const Vec3& offset, const Pose& pose,
                      bool seen) {
  Tracked t{frame, offset, pose, false};
  t.seen = seen;
  grasps_[id] = t;
}

void GraspFrames::remove(int id) { grasps_.erase(id); }

Pose GraspFrames::poseAt(int id, const ros::Time& stamp) {
  auto it = grasps_.find(id);
  if (it == grasps_.end()) return Pose::Identity();
  Tracked& g = it->second;
  try {
    const FrameSample sample = sampleFrame(buffer_, sim_frame_, g.frame, stamp);
    g.last_pose = Pose(tf2::transformToEigen(sample.transform)) * Eigen::Translation3d(g.offset);
    g.before_buffer = sample.before_buffer;
    g.seen = true;
    // Held past the newest transform: stale once that is too old.
    g.stale = sample.after_buffer && !sample.transform.header.stamp.isZero() &&
              (stamp - sample.transform.header.stamp).toSec() > timeout_;
  } catch (const tf2::TransformException&) {
    g.stale = true;  // the frame is gone: keep its last pose
  }
  return g.last_pose;
}

const GraspFrames::Tracked* GraspFrames::find(int id) const {
  auto it = grasps_.find(id);
  return it == grasps_.end() ? nullptr : &it->second;
}

std::vector<std::string> GraspFrames::staleFrames() const {
  std::vector<std::string> out;
  for (const auto& [id, g] : grasps_) {
    if (g.stale) out.push_back(quotedName(g.frame) + " (grasp " + std::to_string(id) + ")");
  }
  return out;
}

}  // namespace cloth_sim::node
