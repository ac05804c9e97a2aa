// Grasps of cloth_sim_node: cloth/grasp and cloth/release, the per-grasp wrench topics, and
// what cloth/state and the markers show of them. The physics (pins following the frame, the
// loads) is the core's (Simulation::addGrasp); here are tf2 and the messages.
#include <cmath>
#include <sstream>

#include <geometry_msgs/WrenchStamped.h>

#include "cloth_sim/node/cloth_sim_node.h"
#include "cloth_sim/node/conversions.h"
#include "cloth_sim/node/grasp_output.h"
#include "cloth_sim/node/names.h"

namespace cloth_sim::node {

std::vector<int> ClothSimNode::selectParticles(const AddGrasp::Request& req,
                                               const Vec3& point) const {
  if (!req.vertices.empty()) return req.vertices;  // Simulation::addGrasp checks them
  settings::kGraspRadius.require(req.radius, "radius");
  const Points& x = sim_.state().positions;
  std::vector<int> chosen;
  int nearest = -1;
  double nearest_distance = INFINITY;
  for (int i = 0; i < sim_.model().particleCount(); ++i) {
    if (sim_.pins().findByVertex(i) != nullptr) continue;  // held already: not grasped again
    const double d = (Vec3(x.col(i)) - point).norm();
    if (req.radius > 0.0 && d <= req.radius) chosen.push_back(i);
    if (d < nearest_distance) {
      nearest_distance = d;
      nearest = i;
    }
  }
  if (req.radius == 0.0 && nearest >= 0) chosen.push_back(nearest);
  if (chosen.empty()) {
    std::ostringstream s;
    s << "radius " << req.radius << " m around (" << point.x() << ", " << point.y() << ", "
      << point.z() << ") m selects no free particle";
    if (nearest >= 0) s << " (the nearest free one, " << nearest << ", is " << nearest_distance << " m away)";
    throw std::invalid_argument(s.str());
  }
  return chosen;
}

bool ClothSimNode::onGrasp(AddGrasp::Request& req, AddGrasp::Response& res) {
  res.id = -1;
  return answer(names::kGrasp, res, [&] {
    const Vec3 offset = toVec3(req.offset);
    requireFinite(offset, "offset");
    if (!std::isfinite(req.radius)) throw std::invalid_argument("radius is not finite");
    const std::string frame = names::tf2Frame(req.frame_id);
    const Pose pose = grasp_frames_.lookup(frame, offset, simStamp());
    const std::vector<int> vertices = selectParticles(req, pose.translation());
    res.id = sim_.addGrasp(vertices, pose);
    grasp_frames_.add(res.id, frame, offset, pose);
    wrench_pubs_[res.id] =
        nh_.advertise<geometry_msgs::WrenchStamped>(names::graspWrench(res.id), 10);
    res.vertices = vertices;
    // Its loads do not follow the midpoint step (docs/method.md, "Grasps and pin forces").
    const bool midpoint = sim_.solverSettings().integrator == Integrator::kImplicitMidpoint;
    return "grasp " + std::to_string(res.id) + " holds " + std::to_string(vertices.size()) +
           " particles on frame '" + frame + "'" +
           (midpoint ? "; its wrench is unreliable under integrator implicit_midpoint (use "
                       "implicit_euler or bdf2 for force feedback)"
                     : "");
  });
}

bool ClothSimNode::onRelease(ReleaseGrasp::Request& req, ReleaseGrasp::Response& res) {
  return answer(names::kRelease, res, [&] {
    sim_.removeGrasp(req.id);  // throws "no grasp with id ..." first
    grasp_frames_.remove(req.id);
    wrench_pubs_.erase(req.id);  // the topic goes away: its wrench stops
    return "grasp " + std::to_string(req.id) + " released";
  });
}

void ClothSimNode::publishWrenches(const ros::Time& stamp) {
  for (const Grasp& g : sim_.grasps()) {
    auto pub = wrench_pubs_.find(g.id);
    const GraspFrames::Tracked* tracked = grasp_frames_.find(g.id);
    if (pub == wrench_pubs_.end() || tracked == nullptr) continue;
    geometry_msgs::WrenchStamped w;
    w.header.stamp = stamp;
    // In the tf frame's axes, the torque about its origin (the ROS reading of the header).
    w.header.frame_id = tracked->frame;
    w.wrench = wrenchInGraspFrame(g, tracked->offset);
    pub->second.publish(w);
  }
}

void ClothSimNode::addGraspInfo(ClothState& state) const {
  for (const Grasp& g : sim_.grasps()) {
    if (const GraspFrames::Tracked* tracked = grasp_frames_.find(g.id)) {
      state.grasps.push_back(toGraspInfo(g, *tracked));
    }
  }
}

void ClothSimNode::forgetGrasps() {
  grasp_frames_.clear();
  wrench_pubs_.clear();
}

}  // namespace cloth_sim::node
