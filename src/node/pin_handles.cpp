#include "cloth_sim/node/pin_handles.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <string>

#include <Eigen/Geometry>
#include <interactive_markers/tools.h>
#include <ros/console.h>

#include "cloth_sim/node/names.h"

namespace cloth_sim::node {
namespace {

using visualization_msgs::InteractiveMarker;
using visualization_msgs::InteractiveMarkerControl;
using visualization_msgs::InteractiveMarkerFeedback;

constexpr double kSamePose = 1e-9;   ///< m; a smaller difference is not worth a republish

/// A control whose local x axis is (x, y, z): the axis of MOVE_AXIS, the normal of MOVE_PLANE.
InteractiveMarkerControl makeControl(const char* name, std::uint8_t mode, double x, double y,
                                     double z) {
  InteractiveMarkerControl c;
  c.name = name;
  c.interaction_mode = mode;
  // interactive_markers::makeQuaternion is not exported by Debian's library: same rotation here.
  const Eigen::Quaterniond q =
      Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitX(), Eigen::Vector3d(x, y, z));
  c.orientation.w = q.w();
  c.orientation.x = q.x();
  c.orientation.y = q.y();
  c.orientation.z = q.z();
  c.orientation_mode = InteractiveMarkerControl::FIXED;  // axes stay the frame's axes
  return c;
}

geometry_msgs::Pose poseAt(const Vec3& p) {
  geometry_msgs::Pose pose;
  pose.position.x = p.x();
  pose.position.y = p.y();
  pose.position.z = p.z();
  pose.orientation.w = 1.0;
  return pose;
}

}  // namespace

std::string pinHandleName(int pin_id) { return names::kPinHandlePrefix + std::to_string(pin_id); }

int pinIdFromHandleName(const std::string& name) {
  const std::size_t prefix = std::char_traits<char>::length(names::kPinHandlePrefix);
  if (name.rfind(names::kPinHandlePrefix, 0) != 0 || name.size() == prefix) return -1;
  char* end = nullptr;
  const long id = std::strtol(name.c_str() + prefix, &end, 10);
  if (*end != '\0' || id < 0 || id > std::numeric_limits<int>::max()) return -1;
  return static_cast<int>(id);
}

InteractiveMarker makePinHandle(int pin_id, const Vec3& target, const std::string& frame_id,
                                double scale) {
  InteractiveMarker m;
  m.header.frame_id = frame_id;
  m.name = pinHandleName(pin_id);
  m.description = "pin " + std::to_string(pin_id);
  m.pose = poseAt(target);
  m.scale = static_cast<float>(scale);

  InteractiveMarkerControl free =
      makeControl("move_3d", InteractiveMarkerControl::MOVE_3D, 1, 0, 0);
  free.always_visible = true;
  visualization_msgs::Marker ball;
  ball.type = visualization_msgs::Marker::SPHERE;
  ball.scale.x = ball.scale.y = ball.scale.z = 0.3 * scale;
  ball.color.r = 1.0f;
  ball.color.g = 0.55f;
  ball.color.a = 0.5f;
  ball.pose.orientation.w = 1.0;
  free.markers.push_back(ball);
  m.controls.push_back(free);

  m.controls.push_back(makeControl("move_x", InteractiveMarkerControl::MOVE_AXIS, 1, 0, 0));
  m.controls.push_back(makeControl("move_y", InteractiveMarkerControl::MOVE_AXIS, 0, 1, 0));
  m.controls.push_back(makeControl("move_z", InteractiveMarkerControl::MOVE_AXIS, 0, 0, 1));
  m.controls.push_back(makeControl("move_xy", InteractiveMarkerControl::MOVE_PLANE, 0, 0, 1));
  interactive_markers::autoComplete(m);
  return m;
}

double handleSizeFor(double cloth_size) {
  return std::isfinite(cloth_size) ? std::clamp(0.1 * cloth_size, 0.02, 0.5) : 0.2;
}

PinHandles::PinHandles(const std::string& topic_ns, std::string frame_id, int max_handles,
                       MoveCallback on_move, double handle_size)
    : server_(topic_ns, "", /*spin_thread=*/false),
      frame_id_(std::move(frame_id)),
      handle_size_(handle_size),
      max_handles_(max_handles),
      on_move_(std::move(on_move)) {}

void PinHandles::sync(const std::vector<Pin>& pins) {
  const bool over_limit = static_cast<int>(pins.size()) > max_handles_;
  if (over_limit != over_limit_) {
    over_limit_ = over_limit;
    if (over_limit) {
      ROS_INFO("%zu pins: more than ~max_interactive_pins = %d, so no pin has a drag handle",
               pins.size(), max_handles_);
    }
  }
  bool changed = false;
  std::map<int, Vec3> wanted;
  if (!over_limit) {
    for (const Pin& p : pins) wanted.emplace(p.id, p.target);
  }
  for (auto it = shown_.begin(); it != shown_.end();) {
    if (wanted.count(it->first)) {
      ++it;
      continue;
    }
    server_.erase(pinHandleName(it->first));
    it = shown_.erase(it);
    changed = true;
  }
  for (const auto& [id, target] : wanted) {
    auto it = shown_.find(id);
    if (it == shown_.end()) {
      server_.insert(makePinHandle(id, target, frame_id_, handle_size_),
                     [this](const auto& feedback) { onFeedback(feedback); });
      shown_.emplace(id, target);
      changed = true;
    } else if ((it->second - target).norm() > kSamePose) {
      server_.setPose(pinHandleName(id), poseAt(target));
      it->second = target;
      changed = true;
    }
  }
  if (changed || dragged_) server_.applyChanges();
  dragged_ = false;
}

void PinHandles::onFeedback(const visualization_msgs::InteractiveMarkerFeedbackConstPtr& fb) {
  if (fb->event_type != InteractiveMarkerFeedback::POSE_UPDATE &&
      fb->event_type != InteractiveMarkerFeedback::MOUSE_UP) {
    return;
  }
  const int id = pinIdFromHandleName(fb->marker_name);
  auto it = shown_.find(id);
  if (it == shown_.end()) return;
  geometry_msgs::PointStamped target;
  target.header = fb->header;
  target.point = fb->pose.position;
  // The server already holds the dragged pose: remember it so sync() does not send it back.
  const Vec3 p(target.point.x, target.point.y, target.point.z);
  if (p.allFinite()) {
    it->second = p;
    dragged_ = true;
  }
  on_move_(id, target);
}

}  // namespace cloth_sim::node
