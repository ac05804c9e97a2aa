/// @file cloth_sim_node.h
/// cloth_sim_node: owns one core Simulation and schedules, converts and publishes. No physics.
#pragma once

#include <algorithm>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <boost/thread/recursive_mutex.hpp>
#include <diagnostic_updater/diagnostic_updater.h>
#include <dynamic_reconfigure/server.h>
#include <ros/ros.h>
#include <std_srvs/Trigger.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include <actionlib/server/simple_action_server.h>

#include <cloth_sim/AddCollider.h>
#include <cloth_sim/AddGrasp.h>
#include <cloth_sim/AddPin.h>
#include <cloth_sim/ClothSimConfig.h>
#include <cloth_sim/ClothState.h>
#include <cloth_sim/GetState.h>
#include <cloth_sim/MoveSphere.h>
#include <cloth_sim/RemoveCollider.h>
#include <cloth_sim/SetState.h>
#include <cloth_sim/StepFramesAction.h>
#include <cloth_sim/PinMove.h>
#include <cloth_sim/ReleaseGrasp.h>
#include <cloth_sim/RemovePin.h>
#include <cloth_sim/RemoveSphere.h>
#include <cloth_sim/SpawnSphere.h>
#include <cloth_sim/Step.h>

#include "cloth_sim/core/simulation/frame_budget.h"
#include "cloth_sim/core/io/scene_limits.h"
#include "cloth_sim/core/simulation/simulation.h"
#include "cloth_sim/node/diagnostics_report.h"
#include "cloth_sim/node/frame_resolver.h"
#include "cloth_sim/node/grasp_frames.h"
#include "cloth_sim/node/log_throttle.h"
#include "cloth_sim/node/marker_builder.h"
#include "cloth_sim/node/names.h"
#include "cloth_sim/node/options.h"
#include "cloth_sim/node/pin_handles.h"
#include "cloth_sim/node/reconfigure_bridge.h"
#include "cloth_sim/node/render_pacer.h"
#include "cloth_sim/node/sim_clock.h"
#include "cloth_sim/node/step_monitor.h"

namespace cloth_sim::node {

/// Frames one cloth/step call may ask for (about 2.8 simulated minutes at 60 Hz, 4.5 s of wall
/// time on a 256-particle cloth): the call holds the node's only thread. Longer runs go through
/// the cloth/step_frames action, which steps in chunks and can be cancelled.
inline constexpr std::uint32_t kMaxFramesPerCall = 10000;

/// The ROS shell around one Simulation (the public contract: docs/ros_interface.md).
///
/// Threading: every callback (timers, subscriber, services, dynamic_reconfigure, drag handles)
/// runs on the global callback queue, which main() spins with one thread; the Simulation is
/// therefore only ever touched by one callback at a time, and an edit that needs a
/// refactorization (a stiffness, the pin set) is applied between two steps. Only the tf2
/// listener has a thread of its own, and it writes only into the (locked) tf2 buffer.
class ClothSimNode {
 public:
  /// Serves @p sim, the simulation of the scene called @p scene_name (buildScene). @p nh is the
  /// namespace of the public names (cloth/...), @p pnh the private one (parameters,
  /// dynamic_reconfigure).
  ClothSimNode(ros::NodeHandle nh, ros::NodeHandle pnh, NodeOptions options,
               std::string scene_name, Simulation sim);

 private:
  // --- wiring (cloth_sim_node.cpp): each called once by the constructor ----------------------
  /// cloth/markers, cloth/state, cloth/points, /clock (with ~publish_clock) and cloth/pin_move.
  void advertiseTopics();
  /// The cloth/... services.
  void advertiseServices();
  /// The "simulation step" status on /diagnostics.
  void startDiagnostics();
  /// The dynamic_reconfigure server, reporting the values in use and calling onReconfigure.
  void startReconfigure();
  /// The pins' drag handles, when ~max_interactive_pins > 0.
  void startPinHandles();
  /// The step, render, diagnostics and summary timers.
  void startTimers();

  // --- scheduling (cloth_sim_node.cpp) --------------------------------------------------------
  /// The step timer: one frame unless paused.
  void step(const ros::SteadyTimerEvent&);
  /// One frame: the core's step, the monitor, cloth/state, the wrenches, /clock, and the
  /// automatic reset when due.
  void stepFrame();
  /// cloth/state (latched) of the last frame, stamped by @p header, with the node's notice.
  void publishState(const std_msgs::Header& header);
  /// publishState at the state's stamp now (after a pause, a reconfigure request).
  void publishStateNow();
  /// With a frame budget: the next frame's substeps from this frame's wall time.
  void adaptSubsteps();
  void render(const ros::SteadyTimerEvent&);
  void logSummary(const ros::SteadyTimerEvent&);
  /// Copies diagnosticsReport() of this period into @p status.
  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& status);
  /// Applies a request through the ReconfigureBridge and logs each field's outcome.
  void onReconfigure(ClothSimConfig& config, std::uint32_t level);
  /// Back to the initial state; @p why goes to the log (throttled when @p automatic).
  void resetSimulation(const std::string& why, bool automatic);
  /// The pins that get drag handles: all but the grasps' (their frame moves them).
  std::vector<Pin> handledPins() const;
  /// A user's input changed something: a divergence after it is a new cause (its first
  /// automatic reset is a reset, not a hold), and the notice of a hold is cleared.
  void userInput();
  /// The automatic reset that would repeat (no input since the last one): instead, the
  /// reconfigured values go back to the last stable ones, the cloth to its initial shape, each
  /// pin whose target is away from its particle's initial position is held there and each
  /// moving kinematic sphere stopped. Returns what was held ("" = nothing: the cause is not an
  /// input, and the caller resets).
  std::string holdInputs();
  /// Removes the spheres that flew beyond ~sphere_cull_distance.
  void cullSpheres();
  /// Logs "<where>: <why>" as a warning, at most once per few seconds per distinct text.
  void refuse(const std::string& where, const std::string& why);
  /// Logs @p text as a warning at most once per few seconds per @p key.
  void warnThrottled(const std::string& key, const std::string& text);

  // --- inputs (node_inputs.cpp) ---------------------------------------------------------------
  void onPinMove(const PinMove::ConstPtr& msg);
  /// Moves pin @p pin_id to @p target (any tf2 frame); a refusal is logged under @p source.
  void movePin(const char* source, int pin_id, const geometry_msgs::PointStamped& target);
  bool onSpawnSphere(SpawnSphere::Request& req, SpawnSphere::Response& res);
  bool onRemoveSphere(RemoveSphere::Request& req, RemoveSphere::Response& res);
  bool onAddPin(AddPin::Request& req, AddPin::Response& res);
  bool onRemovePin(RemovePin::Request& req, RemovePin::Response& res);
  bool onReset(std_srvs::Trigger::Request& req, std_srvs::Trigger::Response& res);

  // --- simulated time (node_time.cpp) ---------------------------------------------------------
  /// The state's simulated time as a ROS time (SimClock).
  ros::Time simStamp() const { return clock_.stamp(sim_.state().time); }
  /// /clock at simStamp(), when ~publish_clock.
  void publishClock();
  bool onPause(std_srvs::Trigger::Request& req, std_srvs::Trigger::Response& res);
  bool onUnpause(std_srvs::Trigger::Request& req, std_srvs::Trigger::Response& res);
  bool onStep(Step::Request& req, Step::Response& res);
  /// The cloth/step_frames action: a new goal, a cancel, and the timer that steps a chunk of
  /// frames per tick until the goal is done or cancelled.
  void onStepGoal();
  void onStepCancel();
  void stepActionTick(const ros::SteadyTimerEvent&);
  /// The action's result now: the frames done so far, the simulated time, its stamp and the
  /// state digest, with @p message.
  StepFramesResult stepFramesResult(const std::string& message) const;

  // --- colliders (node_colliders.cpp) ---------------------------------------------------------
  bool onAddCollider(AddCollider::Request& req, AddCollider::Response& res);
  bool onRemoveCollider(RemoveCollider::Request& req, RemoveCollider::Response& res);
  bool onMoveSphere(MoveSphere::Request& req, MoveSphere::Response& res);
  /// Tracks the tf frame of every body that follows one (the scene's, the robot's links).
  void trackSceneBodies();
  /// Body @p id's frame at simulated time @p time (the simulation's BodyPoseSource): NaN while
  /// tf2 has never had it, so the body is not placed yet.
  Pose bodyPoseAt(int id, double time);
  /// cloth/state's colliders, and a warning for a frame looked up before the tf buffer.
  void addColliderInfo(ClothState& state) const;
  std::vector<ColliderInfo> colliderInfos() const;
  /// Warns (throttled) about every grasp or body frame last looked up before the oldest
  /// transform of the tf buffer (~tf_buffer_duration too short for what was published ahead).
  void warnFramesBeforeBuffer();

  // --- state snapshots (node_state.cpp) -------------------------------------------------------
  bool onGetState(GetState::Request& req, GetState::Response& res);
  bool onSetState(SetState::Request& req, SetState::Response& res);
  /// cloth/frame_state, when subscribed.
  void publishFrameState();

  // --- grasps (node_grasps.cpp) ---------------------------------------------------------------
  bool onGrasp(AddGrasp::Request& req, AddGrasp::Response& res);
  bool onRelease(ReleaseGrasp::Request& req, ReleaseGrasp::Response& res);
  /// The particles a grasp request selects around @p point (m, in ~frame_id).
  std::vector<int> selectParticles(const AddGrasp::Request& req, const Vec3& point) const;
  /// cloth/grasps/<id>/wrench of every grasp, stamped @p stamp, in the grasp frame.
  void publishWrenches(const ros::Time& stamp);
  /// cloth/state's grasps and markers of the grasps.
  void addGraspInfo(ClothState& state) const;
  /// After a reset (which drops every grasp): stop tracking and publishing them.
  void forgetGrasps();
  /// Runs @p action for service @p name: its result is the success message; an exception
  /// becomes success = false with its text as the message (and a throttled warning).
  template <class Response>
  bool answer(const std::string& name, Response& res, const std::function<std::string()>& action);

  NodeOptions options_;
  std::string scene_name_;
  Simulation sim_;
  StepMonitor monitor_;
  /// What runtime inputs may ask (reach: ~sphere_cull_distance), and the cloth's initial centre
  /// and size the markers and the culling use.
  SceneLimits limits_;
  /// ~budget_ms / reconfigure budget_ms > 0: picks each frame's substeps (adaptSubsteps).
  std::optional<FrameBudget> budget_;
  LogThrottle refusals_{5.0};
  MarkerStyle style_;
  /// What dynamic_reconfigure changes: sim_, budget_ and style_.color_mode.
  ReconfigureBridge bridge_{sim_, budget_, style_.color_mode};
  ShownMarkers shown_;
  double ground_size_;  ///< m
  std::uint64_t steps_since_reset_ = 0;
  StepReport last_report_;
  /// ClothState::notice: the refusals of the last reconfigure request ("" = all applied) and
  /// the inputs held back to stop a reset loop.
  std::string reconfigure_notice_, held_notice_;
  /// An automatic reset happened and no input came since: the next one would repeat it.
  bool reset_since_input_ = false;
  /// Frames kept in a row since the last rollback or input, and the reconfigured values in use
  /// once kStableFrames were (what a hold goes back to).
  int kept_in_row_ = 0;
  ClothSimConfig stable_config_;
  RealTimeWindow real_time_;  ///< simulated over wall time since the last diagnostics report

  tf2_ros::Buffer tf_buffer_;
  tf2_ros::TransformListener tf_listener_;
  FrameResolver frames_;
  GraspFrames grasp_frames_;
  GraspFrames body_frames_;  ///< body id -> the tf frame it follows
  std::set<int> shown_bodies_;  ///< body markers in the last marker array
  SimClock clock_;
  bool paused_ = false;
  std::map<int, ros::Publisher> wrench_pubs_;  ///< grasp id -> cloth/grasps/<id>/wrench
  std::set<int> shown_grasps_;                 ///< grasp arrows in the last marker array

  ros::NodeHandle nh_, pnh_;
  ros::Publisher markers_pub_, state_pub_, points_pub_, clock_pub_, frame_state_pub_;
  /// What cloth/get_state kept: the core's snapshot and the node's own tracking of it.
  struct NodeSnapshot {
    SimulationSnapshot sim;
    std::map<int, GraspFrames::Tracked> grasp_frames, body_frames;
    std::uint64_t steps = 0;
  };
  std::map<std::uint32_t, NodeSnapshot> snapshots_;  ///< at most kMaxSnapshots, oldest dropped
  std::uint32_t next_snapshot_ = 0;
  std::unique_ptr<actionlib::SimpleActionServer<StepFramesAction>> step_action_;
  std::uint32_t action_frames_left_ = 0, action_frames_done_ = 0;
  ros::SteadyTimer step_action_timer_;
  ros::Subscriber pin_move_sub_;
  std::vector<ros::ServiceServer> services_;
  diagnostic_updater::Updater diagnostics_;
  /// Given to the reconfigure server so updateConfig() and its own updates cannot interleave.
  boost::recursive_mutex reconfigure_mutex_;
  std::unique_ptr<dynamic_reconfigure::Server<ClothSimConfig>> reconfigure_;
  std::unique_ptr<PinHandles> pin_handles_;
  ros::SteadyTimer step_timer_, render_timer_, diagnostics_timer_, summary_timer_;
  std::uint64_t renders_ = 0;  ///< marker arrays sent; mesh obstacles go with one a second
  RenderPacer pacer_{options_.marker_bandwidth, 1.0 / options_.render_rate};  ///< bytes/s cap
};

template <class Response>
bool ClothSimNode::answer(const std::string& name, Response& res,
                          const std::function<std::string()>& action) {
  try {
    res.message = action();
    res.success = true;
    // An edit is a new input (a divergence after it is a new cause); a query or pause is not.
    const std::string edits[] = {names::kSpawnSphere, names::kRemoveSphere, names::kAddPin,
                                 names::kRemovePin,   names::kReset,        names::kGrasp,
                                 names::kRelease,     names::kAddCollider,  names::kRemoveCollider,
                                 names::kMoveSphere,  names::kSetState};
    if (std::find(std::begin(edits), std::end(edits), name) != std::end(edits)) userInput();
    ROS_INFO("%s: %s", name.c_str(), res.message.c_str());
  } catch (const std::exception& e) {
    res.success = false;
    res.message = e.what();
    refuse(name, res.message);
  }
  return true;  // a refusal is an answer, not a transport failure
}

}  // namespace cloth_sim::node
