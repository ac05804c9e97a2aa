#include "cloth_sim/node/grasp_frames.h"

#include <stdexcept>

#include <tf2/exceptions.h>
#include <tf2_eigen/tf2_eigen.h>

#include "cloth_sim/node/frame_resolver.h"

namespace cloth_sim::node {

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
    try {
      t = buffer_.lookupTransform(sim_frame_, frame, stamp);
    } catch (const tf2::ExtrapolationException&) {
      t = buffer_.lookupTransform(sim_frame_, frame, ros::Time(0));
    }
  } catch (const tf2::TransformException& e) {
    throw std::invalid_argument("frame_id " + quotedName(frame) + " cannot be transformed into '" +
                                sim_frame_ + "': " + e.what());
  }
  return Pose(tf2::transformToEigen(t)) * Eigen::Translation3d(offset);
}

void GraspFrames::add(int id, const std::string& frame, const Vec3& offset, const Pose& pose) {
  grasps_[id] = Tracked{frame, offset, pose, false};
}

void GraspFrames::remove(int id) { grasps_.erase(id); }

Pose GraspFrames::poseAt(int id, const ros::Time& stamp) {
  auto it = grasps_.find(id);
  if (it == grasps_.end()) return Pose::Identity();
  Tracked& g = it->second;
  try {
    try {
      g.last_pose = Pose(tf2::transformToEigen(buffer_.lookupTransform(sim_frame_, g.frame, stamp))) *
                    Eigen::Translation3d(g.offset);
      g.stale = false;
    } catch (const tf2::ExtrapolationException&) {
      // Nothing that recent: hold the latest transform, stale once it is too old.
      const geometry_msgs::TransformStamped latest =
          buffer_.lookupTransform(sim_frame_, g.frame, ros::Time(0));
      g.last_pose = Pose(tf2::transformToEigen(latest)) * Eigen::Translation3d(g.offset);
      g.stale = !latest.header.stamp.isZero() && (stamp - latest.header.stamp).toSec() > timeout_;
    }
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
