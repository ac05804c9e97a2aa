#include "cloth_sim/node/frame_resolver.h"

#include <stdexcept>

#include <tf2/exceptions.h>
#include <tf2_eigen/tf2_eigen.h>

#include "cloth_sim/node/conversions.h"
#include "cloth_sim/node/names.h"

namespace cloth_sim::node {

std::string quotedName(const std::string& name) {
  if (name.size() <= kMaxEchoedName) return "'" + name + "'";
  return "'" + name.substr(0, kMaxEchoedName) + "...' (" + std::to_string(name.size()) +
         " characters)";
}

FrameResolver::FrameResolver(const tf2_ros::Buffer& buffer, std::string target_frame)
    : buffer_(buffer), target_frame_(std::move(target_frame)) {}

Vec3 FrameResolver::point(const geometry_msgs::PointStamped& point,
                          const std::string& what) const {
  const Vec3 p = toVec3(point.point);
  requireFinite(p, what);
  return lookup(point.header, what) * p;
}

Vec3 FrameResolver::vector(const std_msgs::Header& header, const geometry_msgs::Vector3& vector,
                           const std::string& what) const {
  const Vec3 v = toVec3(vector);
  requireFinite(v, what);
  return lookup(header, what).linear() * v;
}

Eigen::Isometry3d FrameResolver::lookup(const std_msgs::Header& header,
                                        const std::string& what) const {
  const std::string frame = names::tf2Frame(header.frame_id);
  if (frame.empty() || frame == target_frame_) return Eigen::Isometry3d::Identity();
  const std::string prefix = what + ": frame " + quotedName(frame);
  if (!buffer_._frameExists(frame)) {
    throw std::invalid_argument(prefix + " is unknown to tf2 (no transform into '" +
                                target_frame_ + "' has been published)");
  }
  try {
    try {
      return tf2::transformToEigen(buffer_.lookupTransform(target_frame_, frame, header.stamp));
    } catch (const tf2::ExtrapolationException&) {
      if (header.stamp.isZero()) throw;
      return tf2::transformToEigen(buffer_.lookupTransform(target_frame_, frame, ros::Time(0)));
    }
  } catch (const tf2::TransformException& e) {
    throw std::invalid_argument(prefix + " cannot be transformed into '" + target_frame_ +
                                "': " + e.what());
  }
}

}  // namespace cloth_sim::node
