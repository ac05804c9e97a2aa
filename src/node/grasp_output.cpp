#include "cloth_sim/node/grasp_output.h"

#include <tf2_eigen/tf2_eigen.h>

#include "cloth_sim/node/conversions.h"

namespace cloth_sim::node {

geometry_msgs::Wrench wrenchInGraspFrame(const Grasp& grasp, const Vec3& offset) {
  const Eigen::Matrix3d to_grasp = grasp.pose.linear().transpose();
  const Vec3 force = to_grasp * grasp.wrench.force;
  geometry_msgs::Wrench w;
  w.force = toVector3Msg(force);
  // About the frame's origin: sum (x_i - o) x F_i = torque about o + offset, plus offset x F.
  w.torque = toVector3Msg(to_grasp * grasp.wrench.torque + offset.cross(force));
  return w;
}

GraspInfo toGraspInfo(const Grasp& grasp, const GraspFrames::Tracked& tracked) {
  GraspInfo info;
  info.id = grasp.id;
  info.frame_id = tracked.frame;
  info.offset = toVector3Msg(tracked.offset);
  info.vertices = grasp.vertices;
  info.pose = tf2::toMsg(Eigen::Isometry3d(grasp.pose));
  info.lag = grasp.lag;
  info.wrench = wrenchInGraspFrame(grasp, tracked.offset);
  info.frame_stale = tracked.stale;
  return info;
}

visualization_msgs::Marker graspArrow(const Grasp& grasp, bool stale, double scale,
                                      const std_msgs::Header& header) {
  visualization_msgs::Marker m;
  m.header = header;
  m.ns = names::kGraspsNs;
  m.id = grasp.id;
  m.type = visualization_msgs::Marker::ARROW;
  m.action = visualization_msgs::Marker::ADD;
  m.pose.orientation.w = 1.0;
  const Vec3 from = grasp.pose.translation();
  Vec3 along = scale * grasp.wrench.force;
  if (!along.allFinite()) along.setZero();
  m.points = {toPointMsg(from), toPointMsg(from + along)};
  m.scale.x = 0.015;  // shaft diameter, m
  m.scale.y = 0.03;   // head diameter, m
  m.scale.z = 0.04;   // head length, m
  m.color.r = stale ? 0.9f : 0.85f;
  m.color.g = stale ? 0.1f : 0.1f;
  m.color.b = stale ? 0.1f : 0.85f;
  m.color.a = 1.0f;
  return m;
}

void appendGraspMarkers(const std::vector<Grasp>& grasps, const GraspFrames& frames, double scale,
                        const std_msgs::Header& header, std::set<int>& shown,
                        visualization_msgs::MarkerArray& out) {
  std::set<int> now;
  for (const Grasp& g : grasps) {
    const GraspFrames::Tracked* t = frames.find(g.id);
    out.markers.push_back(graspArrow(g, t != nullptr && t->stale, scale, header));
    now.insert(g.id);
  }
  for (int id : shown) {
    if (now.count(id)) continue;
    visualization_msgs::Marker m;
    m.header = header;
    m.ns = names::kGraspsNs;
    m.id = id;
    m.action = visualization_msgs::Marker::DELETE;
    out.markers.push_back(m);
  }
  shown = std::move(now);
}

}  // namespace cloth_sim::node
