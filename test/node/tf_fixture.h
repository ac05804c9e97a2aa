// Transforms written by hand for the node's unit tests on a tf2 buffer (no master).
#pragma once

#include <string>

#include <geometry_msgs/TransformStamped.h>
#include <ros/time.h>
#include <tf2/LinearMath/Quaternion.h>

#include "cloth_sim/core/linalg/types.h"

namespace cloth_sim::node {

/// @p child in @p parent: translated by @p t (m), turned by @p yaw (rad) about z, at @p stamp (s).
inline geometry_msgs::TransformStamped transform(const std::string& parent,
                                                 const std::string& child, const Vec3& t,
                                                 double yaw, double stamp) {
  geometry_msgs::TransformStamped tf;
  tf.header.frame_id = parent;
  tf.header.stamp = ros::Time(stamp);
  tf.child_frame_id = child;
  tf.transform.translation.x = t.x();
  tf.transform.translation.y = t.y();
  tf.transform.translation.z = t.z();
  tf2::Quaternion q;
  q.setRPY(0, 0, yaw);
  tf.transform.rotation.x = q.x();
  tf.transform.rotation.y = q.y();
  tf.transform.rotation.z = q.z();
  tf.transform.rotation.w = q.w();
  return tf;
}

}  // namespace cloth_sim::node
