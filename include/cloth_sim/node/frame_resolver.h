/// @file frame_resolver.h
/// Brings points and vectors given in any tf2 frame into the simulation frame (~frame_id).
#pragma once

#include <cstddef>
#include <string>

#include <Eigen/Geometry>
#include <geometry_msgs/PointStamped.h>
#include <geometry_msgs/Vector3.h>
#include <std_msgs/Header.h>
#include <tf2_ros/buffer.h>

#include "cloth_sim/core/linalg/types.h"

namespace cloth_sim::node {

/// Characters of a name a message repeats: a 100 kB frame name is not echoed back whole.
inline constexpr std::size_t kMaxEchoedName = 64;
/// @p name in quotes, cut to kMaxEchoedName characters with its length when longer.
std::string quotedName(const std::string& name);

/// Transforms inputs into the target frame with a tf2 buffer it does not own.
///
/// The transform is looked up at the input's stamp when the buffer has it, else the latest one
/// (a stamp of 0 asks for the latest directly), so a point stamped "now" by a client whose clock
/// runs a little ahead is still accepted. An empty frame_id means the target frame; one leading
/// '/' (tf1 style) is ignored. Nothing blocks: a transform tf2 does not have yet is refused.
class FrameResolver {
 public:
  FrameResolver(const tf2_ros::Buffer& buffer, std::string target_frame);

  /// @p point in the target frame (m). Throws std::invalid_argument naming @p what: a non-finite
  /// coordinate, an unknown frame, or no transform between the two frames.
  Vec3 point(const geometry_msgs::PointStamped& point, const std::string& what) const;
  /// The free vector @p vector (e.g. a velocity) given in @p header's frame, rotated into the
  /// target frame (no translation). Throws as point().
  Vec3 vector(const std_msgs::Header& header, const geometry_msgs::Vector3& vector,
              const std::string& what) const;

  const std::string& targetFrame() const { return target_frame_; }

 private:
  /// The transform target <- header.frame_id as an isometry, or throws.
  Eigen::Isometry3d lookup(const std_msgs::Header& header, const std::string& what) const;

  const tf2_ros::Buffer& buffer_;
  std::string target_frame_;
};

}  // namespace cloth_sim::node
