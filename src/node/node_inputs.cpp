// The inputs of cloth_sim_node: the pin_move topic, the services and the drag handles. Each
// brings its points into ~frame_id (FrameResolver refuses a non-finite one or an unknown frame)
// and hands the values to the core, whose checks (the edits of Simulation, SceneLimits) refuse
// what it cannot use with a message saying why; the node adds no rule of its own, and a refusal
// leaves the simulation untouched (the core edits validate before they change).
#include <sstream>

#include "cloth_sim/node/cloth_sim_node.h"
#include "cloth_sim/node/conversions.h"
#include "cloth_sim/node/names.h"

namespace cloth_sim::node {
namespace {

std::string str(const Vec3& v) {
  std::ostringstream s;
  s << "(" << v.x() << ", " << v.y() << ", " << v.z() << ")";
  return s.str();
}

}  // namespace

void ClothSimNode::movePin(const char* source, int pin_id,
                           const geometry_msgs::PointStamped& target) {
  try {
    const Vec3 point = frames_.point(target, "target");
    // A target beyond the cloth's reach would stretch it past what it can follow.
    limits_.checkPinTarget("target", point);
    sim_.movePin(pin_id, point);
    userInput();
  } catch (const std::exception& e) {
    refuse(source, "pin " + std::to_string(pin_id) + ": " + e.what());
  }
}

void ClothSimNode::onPinMove(const PinMove::ConstPtr& msg) {
  movePin(names::kPinMove, msg->id, msg->target);
}

bool ClothSimNode::onSpawnSphere(SpawnSphere::Request& req, SpawnSphere::Response& res) {
  res.id = -1;
  return answer(names::kSpawnSphere, res, [&] {
    const Vec3 center = frames_.point(req.center, "center");
    const Vec3 velocity = frames_.vector(req.center.header, req.velocity, "velocity");
    const SphereCollider sphere = sphereFromRequest(req, center, velocity);  // a valid sphere
    limits_.checkSphere("", sphere, sim_.substepTime());  // what the cloth can follow
    SceneLimits::checkSphereAroundPins("", sphere, sim_.pins().pins(), sim_.state().positions);
    res.id = sim_.addSphere(sphere);
    return "sphere " + std::to_string(res.id) + " at " + str(center) + " m, radius " +
           std::to_string(sphere.radius) + " m, velocity " + str(velocity) + " m/s in '" +
           options_.frame_id + "'";
  });
}

bool ClothSimNode::onRemoveSphere(RemoveSphere::Request& req, RemoveSphere::Response& res) {
  return answer(names::kRemoveSphere, res, [&] {
    sim_.removeSphere(req.id);
    return "sphere " + std::to_string(req.id) + " removed";
  });
}

bool ClothSimNode::onAddPin(AddPin::Request& req, AddPin::Response& res) {
  res.id = -1;
  res.vertex = -1;
  return answer(names::kAddPin, res, [&] {
    // -1 = the particle nearest to 'point'; any other vertex is the core's to check.
    const int vertex =
        req.vertex == -1 ? sim_.nearestParticle(frames_.point(req.point, "point")) : req.vertex;
    res.id = sim_.addPinHere(vertex, req.stiffness);
    res.vertex = vertex;
    return "pin " + std::to_string(res.id) + " holds vertex " + std::to_string(vertex) +
           " at " + str(sim_.state().positions.col(vertex)) + " m" +
           (req.stiffness > 0.0 ? " (soft, " + std::to_string(req.stiffness) + " N/m)" : "");
  });
}

bool ClothSimNode::onRemovePin(RemovePin::Request& req, RemovePin::Response& res) {
  return answer(names::kRemovePin, res, [&] {
    sim_.removePin(req.id);
    return "pin " + std::to_string(req.id) + " removed";
  });
}

bool ClothSimNode::onReset(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
  return answer(names::kReset, res, [&] {
    resetSimulation("requested on cloth/reset", /*automatic=*/false);
    return "simulation reset to the initial state of scene '" + scene_name_ + "' (pins, spheres)";
  });
}

}  // namespace cloth_sim::node
