// Rigid-body colliders of cloth_sim_node: cloth/add_collider, cloth/remove_collider,
// cloth/move_sphere, the tf frames the bodies follow (the scene's, the robot's links, the
// service's) and what cloth/state shows of them. The contact physics is the core's
// (collideWithBodies); here are tf2 and the messages.
#include <limits>

#include "cloth_sim/node/body_messages.h"
#include "cloth_sim/node/cloth_sim_node.h"
#include "cloth_sim/node/conversions.h"
#include "cloth_sim/node/names.h"

namespace cloth_sim::node {

void ClothSimNode::trackSceneBodies() {
  body_frames_.clear();
  for (const BodyCollider& b : sim_.colliders().bodies().bodies()) {
    if (b.follows_frame) body_frames_.add(b.id, names::tf2Frame(b.name), Vec3::Zero(), Pose::Identity(), false);
  }
}

Pose ClothSimNode::bodyPoseAt(int id, double time) {
  const Pose pose = body_frames_.poseAt(id, clock_.stamp(time));
  const GraspFrames::Tracked* tracked = body_frames_.find(id);
  if (tracked == nullptr || !tracked->seen) {
    Pose nowhere;
    nowhere.matrix().setConstant(std::numeric_limits<double>::quiet_NaN());
    return nowhere;  // not placed: the body waits for its frame
  }
  return pose;
}

bool ClothSimNode::onAddCollider(AddCollider::Request& req, AddCollider::Response& res) {
  res.id = -1;
  return answer(names::kAddCollider, res, [&] {
    const std::string frame = req.frame_id.empty() ? options_.frame_id : names::tf2Frame(req.frame_id);
    const Pose frame_pose = grasp_frames_.lookup(frame, Vec3::Zero(), simStamp());  // known?
    BodyCollider body = bodyFromRequest(req, resolveMeshUrl);
    if (body.name.empty()) body.name = frame;
    body.follows_frame = !req.still && frame != options_.frame_id;
    body.frame_pose = frame_pose;
    res.id = sim_.addBody(body);
    sim_.setBodyPose(res.id, frame_pose);  // there now, sweeping nothing
    if (body.follows_frame) body_frames_.add(res.id, frame, Vec3::Zero(), frame_pose);
    return std::string(bodyShapeName(body.geometry.shape)) + " collider " + std::to_string(res.id) +
           (body.follows_frame ? " follows frame '" : " placed still at frame '") + frame + "'";
  });
}

bool ClothSimNode::onRemoveCollider(RemoveCollider::Request& req, RemoveCollider::Response& res) {
  return answer(names::kRemoveCollider, res, [&] {
    sim_.removeBody(req.id);
    body_frames_.remove(req.id);
    return "collider " + std::to_string(req.id) + " removed";
  });
}

bool ClothSimNode::onMoveSphere(MoveSphere::Request& req, MoveSphere::Response& res) {
  return answer(names::kMoveSphere, res, [&] {
    const Vec3 center = frames_.point(req.center, "center");
    const Vec3 velocity = frames_.vector(req.center.header, req.velocity, "velocity");
    const SphereCollider* s = sim_.colliders().findSphere(req.id);
    if (s == nullptr) throw std::invalid_argument("no sphere with id " + std::to_string(req.id));
    SphereCollider moved = *s;
    moved.center = center;
    moved.velocity = velocity;
    limits_.checkSphere("", moved, sim_.substepTime());  // reach and speed, as at spawn
    SceneLimits::checkSphereAroundPins("", moved, sim_.pins().pins(), sim_.state().positions);
    sim_.moveSphere(req.id, center, velocity);
    return "sphere " + std::to_string(req.id) + " moving to the new centre";
  });
}

std::vector<ColliderInfo> ClothSimNode::colliderInfos() const {
  std::vector<ColliderInfo> out;
  for (const BodyCollider& b : sim_.colliders().bodies().bodies()) {
    const GraspFrames::Tracked* t = body_frames_.find(b.id);
    out.push_back(toColliderInfo(b, t != nullptr ? t->frame : options_.frame_id,
                                 t != nullptr && t->stale));
  }
  return out;
}

void ClothSimNode::addColliderInfo(ClothState& state) const { state.colliders = colliderInfos(); }

void ClothSimNode::warnFramesBeforeBuffer() {
  for (const GraspFrames* frames : {&grasp_frames_, &body_frames_}) {
    for (const auto& [id, t] : frames->all()) {
      if (!t.before_buffer) continue;
      warnThrottled("before buffer " + t.frame,
                    "frame '" + t.frame + "' was looked up before the oldest transform the tf "
                    "buffer keeps: holding that oldest pose. A trajectory published ahead must "
                    "span less than ~tf_buffer_duration (" +
                        std::to_string(options_.tf_buffer_duration) + " s)");
    }
  }
}

}  // namespace cloth_sim::node
