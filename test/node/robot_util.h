// Helpers of the rostests that drive a paused node publishing /clock (robot_test.cpp,
// pinch_test.cpp, tf_buffer_test.cpp, grasp_test.cpp): stepping it, publishing tf trajectories
// ahead in simulated time, and keeping every message of a topic.
#pragma once

#include <cmath>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <tf2_msgs/TFMessage.h>

#include <cloth_sim/Step.h>

#include "ros_test_util.h"

namespace cloth_sim::test {

inline void wallSleep(double s) { ros::WallDuration(s).sleep(); }

inline Step::Response step(std::uint32_t frames) {
  Step::Request req;
  req.frames = frames;
  const Step::Response res = call<Step>(names::kStep, req);
  EXPECT_TRUE(res.success) << res.message;
  return res;
}

/// The ROS stamp of simulated time 0 (the node's clock origin).
inline ros::Time simOrigin() {
  const Step::Response now = step(0);
  return now.stamp - ros::Duration(now.sim_time);
}

/// A frame's pose at simulated time t.
using Trajectory = std::function<Eigen::Isometry3d(double t)>;

/// Publishes each of @p frames (child of "world") at every @p dt of simulated time in [t0, t1]
/// after @p origin, in one /tf message, and waits until the node has it.
inline void publishAhead(const ros::Time& origin, double t0, double t1, double dt,
                         const std::vector<std::pair<std::string, Trajectory>>& frames) {
  static ros::Publisher pub = ros::NodeHandle().advertise<tf2_msgs::TFMessage>("/tf", 10);
  EXPECT_TRUE(waitForSubscriber(pub));
  tf2_msgs::TFMessage msg;
  for (int k = static_cast<int>(std::ceil(t0 / dt - 1e-9)); k * dt <= t1 + 1e-9; ++k) {
    const double t = k * dt;
    for (const auto& [name, pose] : frames) {
      const Eigen::Isometry3d p = pose(t);
      const Eigen::Quaterniond q(p.linear());
      geometry_msgs::TransformStamped tf;
      tf.header.frame_id = "world";
      tf.header.stamp = origin + ros::Duration(t);
      tf.child_frame_id = name;
      tf.transform.translation.x = p.translation().x();
      tf.transform.translation.y = p.translation().y();
      tf.transform.translation.z = p.translation().z();
      tf.transform.rotation.x = q.x();
      tf.transform.rotation.y = q.y();
      tf.transform.rotation.z = q.z();
      tf.transform.rotation.w = q.w();
      msg.transforms.push_back(tf);
    }
  }
  pub.publish(msg);
  wallSleep(1.0);  // into the node's tf2 buffer before it steps
}

/// Keeps every message of one topic (bounded).
template <class M>
class Collector {
 public:
  explicit Collector(const std::string& topic)
      : sub_(ros::NodeHandle().subscribe<M>(
            topic, 2000,
            boost::function<void(const boost::shared_ptr<const M>&)>(
                [this](const boost::shared_ptr<const M>& m) {
                  std::lock_guard<std::mutex> lock(mutex_);
                  all_.push_back(*m);
                  if (all_.size() > 8000) all_.erase(all_.begin(), all_.begin() + 1000);
                }))) {}
  std::vector<M> all() {
    std::lock_guard<std::mutex> lock(mutex_);
    return all_;
  }
  void clear() {
    std::lock_guard<std::mutex> lock(mutex_);
    all_.clear();
  }
  /// The first message kept that satisfies @p pred, within @p timeout wall s.
  std::optional<M> waitFor(const std::function<bool(const M&)>& pred, double timeout = 10.0) {
    const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(timeout);
    while (ros::WallTime::now() < end) {
      for (const M& m : all()) {
        if (pred(m)) return m;
      }
      wallSleep(0.02);
    }
    return std::nullopt;
  }
  /// Waits until @p count messages arrived (false after @p timeout wall s).
  bool waitForCount(std::size_t count, double timeout = 60.0) {
    const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(timeout);
    while (ros::WallTime::now() < end) {
      if (all().size() >= count) return true;
      wallSleep(0.02);
    }
    return false;
  }
  std::size_t subscribers() const { return sub_.getNumPublishers(); }

 private:
  std::mutex mutex_;
  std::vector<M> all_;
  ros::Subscriber sub_;
};

inline Eigen::Isometry3d at(double x, double y, double z) {
  return Eigen::Isometry3d(Eigen::Translation3d(x, y, z));
}

}  // namespace cloth_sim::test
