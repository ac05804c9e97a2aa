/// @file conversions.h
/// ROS messages <-> core types. Every function is pure; the ones that read a request check it
/// and throw std::invalid_argument with a message that says what is wrong and why.
#pragma once

#include <cstdint>
#include <string>

#include <geometry_msgs/Point.h>
#include <geometry_msgs/Vector3.h>
#include <std_msgs/Header.h>

#include <cloth_sim/ClothState.h>
#include <cloth_sim/PinInfo.h>
#include <cloth_sim/SpawnSphere.h>
#include <cloth_sim/SphereInfo.h>

#include "cloth_sim/core/collision/colliders.h"
#include "cloth_sim/core/model/pins.h"
#include "cloth_sim/core/settings/settings_table.h"
#include "cloth_sim/core/simulation/simulation.h"

namespace cloth_sim::node {

Vec3 toVec3(const geometry_msgs::Point& p);
Vec3 toVec3(const geometry_msgs::Vector3& v);
geometry_msgs::Point toPointMsg(const Vec3& v);
geometry_msgs::Vector3 toVector3Msg(const Vec3& v);

/// Throws std::invalid_argument "<what> (x, y, z) is not finite" unless every coordinate is.
void requireFinite(const Vec3& v, const std::string& what);

/// The sphere a cloth/spawn_sphere request asks for, with @p center (m) and @p velocity (m/s)
/// already transformed into ~frame_id. Refuses (std::invalid_argument) what the core refuses of
/// any sphere, with the core's message (Colliders::addSphere: a non-finite centre or velocity, a
/// radius, mass, friction or restitution outside its settings_table.h range); the simulation's
/// own limits (SceneLimits::checkSphere) are the caller's to ask next.
SphereCollider sphereFromRequest(const SpawnSphere::Request& request, const Vec3& center,
                                 const Vec3& velocity);

/// A pin as cloth/state reports it; @p vertex_position (m) is where its particle is now (force
/// zero and grasp -1: toClothState fills them in).
PinInfo toPinInfo(const Pin& pin, const Vec3& vertex_position);
SphereInfo toSphereInfo(const SphereCollider& sphere);

/// Node-side counters reported with each step in cloth/state.
struct StepCounters {
  std::uint64_t step = 0;                  ///< steps since start or the last reset
  std::uint32_t consecutive_failures = 0;  ///< rolled-back steps in a row
  std::uint32_t divergence_resets = 0;     ///< automatic resets since start
};

/// cloth/state after a step: @p report is what the step did, @p sim the simulation after it.
/// The header is used as given (stamp and frame are the caller's). Each pin carries its load
/// (Simulation::pinLoads) and its grasp; the grasps array is left to the node (GraspInfo needs
/// the frames it tracks, toGraspInfo).
ClothState toClothState(const Simulation& sim, const StepReport& report,
                        const StepCounters& counters, const std_msgs::Header& header);

/// Bytes of cloth/frame_state messages a lagging subscriber may leave queued at the publisher.
constexpr double kFrameStateQueueBytes = 64e6;
/// Queue of the cloth/frame_state publisher for a cloth of @p particles: a cloth/step call
/// publishes its frames back to back, and a subscriber must see every one (a lockstep
/// controller), so the queue holds as many frames as one call may ask for (@p frames_per_call),
/// as far as kFrameStateQueueBytes of positions and velocities (48 bytes a particle) allow;
/// never fewer than 10.
std::uint32_t frameStateQueue(int particles, std::uint32_t frames_per_call);

}  // namespace cloth_sim::node
