/// @file names.h
/// Every name cloth_sim_node publishes, serves or draws under, and its frame conventions, in one
/// place (the public contract: docs/ros_interface.md). The node, its units and its tests use
/// these instead of literals; the parameters are read by options.h.
#pragma once

#include <string>

namespace cloth_sim::node::names {

/// The node's name (ros::init): its private namespace holds the parameters and the
/// dynamic_reconfigure server.
inline constexpr const char* kNode = "cloth_sim_node";

// --- topics, relative to the node's namespace unless they start with '/' ----------------------

inline constexpr const char* kMarkers = "cloth/markers";   ///< out: visualization_msgs/MarkerArray
inline constexpr const char* kState = "cloth/state";       ///< out: cloth_sim/ClothState
inline constexpr const char* kPoints = "cloth/points";     ///< out: sensor_msgs/PointCloud2
inline constexpr const char* kClock = "/clock";            ///< out, with ~publish_clock only
inline constexpr const char* kPinMove = "cloth/pin_move";  ///< in: cloth_sim/PinMove
/// out: diagnostic_msgs/DiagnosticArray, published by diagnostic_updater (kDiagnosticsTask).
inline constexpr const char* kDiagnostics = "/diagnostics";
/// out: cloth_sim/FrameState, every particle's position and velocity after each frame, built
/// only while subscribed.
inline constexpr const char* kFrameState = "cloth/frame_state";
/// Namespace of the drag handles' interactive marker server (its update, update_full and
/// feedback topics live under it).
inline constexpr const char* kPinHandles = "cloth/pin_handles";
/// out: geometry_msgs/WrenchStamped of grasp @p id, "cloth/grasps/<id>/wrench", advertised by
/// cloth/grasp and gone at cloth/release.
inline std::string graspWrench(int id) { return "cloth/grasps/" + std::to_string(id) + "/wrench"; }

// --- services ----------------------------------------------------------------------------------

inline constexpr const char* kSpawnSphere = "cloth/spawn_sphere";    ///< cloth_sim/SpawnSphere
inline constexpr const char* kRemoveSphere = "cloth/remove_sphere";  ///< cloth_sim/RemoveSphere
inline constexpr const char* kAddPin = "cloth/add_pin";              ///< cloth_sim/AddPin
inline constexpr const char* kRemovePin = "cloth/remove_pin";        ///< cloth_sim/RemovePin
inline constexpr const char* kReset = "cloth/reset";                 ///< std_srvs/Trigger
inline constexpr const char* kGrasp = "cloth/grasp";                 ///< cloth_sim/AddGrasp
inline constexpr const char* kRelease = "cloth/release";             ///< cloth_sim/ReleaseGrasp
inline constexpr const char* kPause = "cloth/pause";                 ///< std_srvs/Trigger
inline constexpr const char* kUnpause = "cloth/unpause";             ///< std_srvs/Trigger
inline constexpr const char* kStep = "cloth/step";                   ///< cloth_sim/Step
inline constexpr const char* kAddCollider = "cloth/add_collider";        ///< cloth_sim/AddCollider
inline constexpr const char* kRemoveCollider = "cloth/remove_collider";  ///< cloth_sim/RemoveCollider
inline constexpr const char* kMoveSphere = "cloth/move_sphere";          ///< cloth_sim/MoveSphere
inline constexpr const char* kGetState = "cloth/get_state";              ///< cloth_sim/GetState
inline constexpr const char* kSetState = "cloth/set_state";              ///< cloth_sim/SetState
/// The cloth_sim/StepFrames action (its goal, cancel, status, feedback and result topics).
inline constexpr const char* kStepFrames = "cloth/step_frames";
/// dynamic_reconfigure's service in the private namespace: "cloth_sim_node/set_parameters".
inline std::string setParameters() { return std::string(kNode) + "/set_parameters"; }

// --- diagnostics -------------------------------------------------------------------------------

/// The status the node adds to /diagnostics ("cloth_sim_node: simulation step").
inline constexpr const char* kDiagnosticsTask = "simulation step";
/// Hardware id of the diagnostics: this prefix and the scene's name.
inline constexpr const char* kHardwareIdPrefix = "cloth_sim:";

// --- where a refusal or a change is logged (besides the topic and service names) ---------------

inline constexpr const char* kReconfigure = "reconfigure";  ///< "reconfigure <field>: <why>"

// --- marker namespaces of cloth/markers (ids: 0 for the cloth and ground, else the core id) ----

inline constexpr const char* kClothNs = "cloth";          ///< one TRIANGLE_LIST
inline constexpr const char* kPinsNs = "pins";            ///< one SPHERE per pin, at its target
inline constexpr const char* kSpheresNs = "spheres";      ///< one SPHERE per sphere collider
inline constexpr const char* kGroundNs = "ground";        ///< one thin CUBE, when there is a ground
inline constexpr const char* kObstaclesNs = "obstacles";  ///< one TRIANGLE_LIST per mesh obstacle
inline constexpr const char* kGraspsNs = "grasps";        ///< one ARROW per grasp (id = grasp id)
/// One marker per rigid-body collider (id = its id; a capsule's caps 1e6 + id and 2e6 + id).
inline constexpr const char* kBodiesNs = "bodies";

/// Prefix of a pin's drag handle name: "pin_<id>".
inline constexpr const char* kPinHandlePrefix = "pin_";

// --- frames and time ---------------------------------------------------------------------------

/// ~frame_id's default: the simulation frame (REP-103, z up); demo.launch publishes
/// world -> map as identity.
inline constexpr const char* kDefaultFrame = "world";
/// With ~publish_clock, simulated time 0 is this ROS time (s): a ROS time of 0 means "no time
/// yet" to ROS nodes and "the latest" to tf2.
inline constexpr int kSimTimeOriginSec = 1;
/// A frame name as tf2 knows it: one leading '/' (tf1 style) dropped.
inline std::string tf2Frame(std::string frame) {
  if (!frame.empty() && frame.front() == '/') frame.erase(0, 1);
  return frame;
}

}  // namespace cloth_sim::node::names
