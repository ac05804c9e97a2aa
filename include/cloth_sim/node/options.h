/// @file options.h
/// Startup parameters of cloth_sim_node: read from the private namespace into a plain struct and
/// validated in one place, every error naming its parameter (cartographer_ros style).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <xmlrpcpp/XmlRpcValue.h>

#include "cloth_sim/core/io/scene.h"

namespace cloth_sim::node {

/// What cloth_sim_node reads once at startup (the run-time knobs are dynamic_reconfigure's).
struct NodeOptions {
  /// ~scene: a scene YAML file, or the bare name of a shipped scene ("drape" means
  /// <package>/config/scenes/drape.yaml). Required.
  std::string scene;
  /// ~frame_id: the frame the simulation lives in; every output is in it and every input is
  /// transformed into it with tf2.
  std::string frame_id = "world";
  /// ~render_rate, Hz (settings::kRenderRate): rate of cloth/markers (independent of the step
  /// rate).
  double render_rate = 30.0;
  /// ~solver: replaces the scene's solver when not empty (a name from solverNames()).
  std::string solver;
  /// ~iterations: replaces the scene's iterations per step when > 0; 0 keeps the scene's (range:
  /// settings::kIterations).
  int iterations = 0;
  /// ~substeps: replaces the scene's implicit steps per frame when > 0; 0 keeps the scene's
  /// (range: settings::kSubsteps).
  int substeps = 0;
  /// ~error_tolerance, m, [0, 1] (settings::kErrorTolerance): replaces the scene's position
  /// error a frame may make when given; 0: fixed substeps and iterations. With a scene that
  /// leaves its substeps to the simulator (or gives 0) the substeps follow it too.
  std::optional<double> error_tolerance;
  /// ~threads (settings::kThreads): threads of the simulation's kernels and of the marker and
  /// point-cloud building, 0 = every core; unset keeps the scene's solver.threads (default 0).
  /// The results are the same for any count.
  std::optional<int> threads;
  /// ~self_collision: turns the cloth's self-collision on or off whatever the scene says; unset
  /// keeps the scene's (its self_collision field; thickness and friction come from there, or
  /// their defaults). dynamic_reconfigure's self_collision switches it at run time.
  std::optional<bool> self_collision;
  /// ~max_rollbacks (settings::kMaxRollbacks): after this many rolled-back (diverged) steps in
  /// a row the node resets the simulation to its initial state (see docs/ros_interface.md,
  /// "Divergence").
  int max_rollbacks = 30;
  /// ~strain_color_scale (settings::kStrainColorScale): the strain drawn at full colour
  /// (0.05 = 5 %).
  double strain_color_scale = 0.05;
  /// ~shading: darken the cloth colours by a fixed light, so folds are visible in RViz.
  bool shading = true;
  /// ~color_mode: "strain" (the cloth coloured by strain) or "shaded" (one colour, shading
  /// only); also a dynamic_reconfigure parameter.
  std::string color_mode = "strain";
  /// ~sphere_cull_distance, m (settings::kSphereCullDistance): a sphere farther than this from
  /// the cloth's initial centre is removed (a thrown kinematic sphere flies on forever
  /// otherwise).
  double sphere_cull_distance = 20.0;
  /// ~max_interactive_pins (settings::kMaxInteractivePins): pins get RViz drag handles while
  /// there are at most this many (a fully pinned edge would bury the cloth under handles);
  /// 0 = never.
  int max_interactive_pins = 16;
  /// ~summary_period, s (settings::kSummaryPeriod): log a one-line summary of the simulation
  /// this often; 0 = never.
  double summary_period = 0.0;
  /// ~publish_clock: publish the simulated time on /clock after every frame (the nodes that
  /// should follow it need /use_sim_time true; launch/cloth_sim.launch sets both together).
  bool publish_clock = false;
  /// ~real_time_factor, [0, 1000] (settings::kRealTimeFactor): simulated seconds per wall
  /// second; 0 = step as fast as the machine can.
  double real_time_factor = 1.0;
  /// ~budget_ms, ms, [0, 1000] (settings::kFrameBudget): when > 0, the substeps per frame adapt
  /// to keep a frame's wall time within this (FrameBudget); 0 = the substeps stay as set.
  double budget_ms = 0.0;
  /// ~frame_deadline_ms, ms, [0, 60000] (settings::kFrameDeadline; 0 = none): the wall time a
  /// frame may take before its work is cut (Simulation::setFrameDeadline), so that no setting
  /// (100,000 iterations, 1,000 substeps) keeps services and Ctrl-C waiting.
  double frame_deadline_ms = 200.0;
  /// ~start_paused: wait for cloth/unpause or cloth/step before the first frame.
  bool start_paused = false;
  /// ~grasp_frame_timeout, s, > 0 (settings::kGraspFrameTimeout): a grasp frame whose latest
  /// transform is older than this at a substep's stamp is reported stale (it holds its pose).
  double grasp_frame_timeout = 0.5;
  /// ~force_arrow_scale, m/N, >= 0 (settings::kForceArrowScale): length of a grasp's force arrow.
  double force_arrow_scale = 0.5;
  /// ~marker_bandwidth, bytes/s (settings::kMarkerBandwidth): cloth/markers is sent at
  /// ~render_rate, or less often when its arrays are large, so as not to exceed this
  /// (RenderPacer; 12 MB/s keeps 30 Hz up to a 40 x 40 cloth, drape's).
  double marker_bandwidth = 12e6;
  /// ~tf_buffer_duration, s (settings::kTfBufferDuration): how much history the node's tf2
  /// buffer keeps. A trajectory published ahead is followed from its start only if it spans
  /// less than this: older transforms are dropped as newer ones arrive (a lookup before the
  /// oldest kept one holds it and warns).
  double tf_buffer_duration = 120.0;
  /// ~robot_description: the URDF text; empty = the global parameter robot_description (read
  /// only when ~robot_links is set).
  std::string robot_description;
  /// ~robot_links: the links whose collision geometry becomes colliders on their tf frames
  /// (urdfColliders); empty = none.
  std::vector<std::string> robot_links;
  /// ~robot_margin, m (settings::kBodyMargin): distance the cloth keeps from those links.
  double robot_margin = 0.005;
  /// ~robot_friction (settings::kFriction): their Coulomb friction coefficient.
  double robot_friction = 0.5;
};

/// Reads the options from @p private_params, the private namespace as one XmlRpc struct (what
/// `getParam("~", value)` gives; an invalid value stands for an empty namespace). Absent keys
/// keep their defaults, an integer is accepted where a number is expected, and unknown keys are
/// left alone (dynamic_reconfigure keeps its own parameters there too). Validates the result.
/// Throws std::invalid_argument: "parameter '~render_rate': expected a number, got a string".
NodeOptions parseNodeOptions(const XmlRpc::XmlRpcValue& private_params);

/// Checks every field against its rule (a number against its entry of settings_table.h).
/// Throws std::invalid_argument naming the parameter, its value and the rule, e.g.
/// "parameter '~render_rate': -3 Hz must be in (0, 1000]" (Setting::refusal).
void validateNodeOptions(const NodeOptions& options);

/// The file ~scene names: a bare name (no '/' and no ".yaml") becomes
/// <scene_dir>/<name>.yaml; anything else is a path and is returned as given.
std::string resolveScenePath(const std::string& scene, const std::string& scene_dir);

/// The shipped scenes: the stems of the .yaml files in @p scene_dir, sorted ("drape", ...).
std::vector<std::string> shippedScenes(const std::string& scene_dir);

/// Loads the scene file of @p options (resolved against @p scene_dir) and applies ~solver,
/// ~iterations, ~substeps, ~threads and ~self_collision to it (checked by validateNodeOptions). Throws
/// std::invalid_argument "parameter '~scene': <what is wrong>" for a missing or invalid file; a
/// bare name that is no shipped scene gets the list of shipped scenes (shippedScenes).
SceneConfig loadScene(const NodeOptions& options, const std::string& scene_dir);

/// The simulation of @p scene (from loadScene). Throws std::invalid_argument
/// "parameter '~scene': <what is wrong>" when it cannot be built (e.g. a pin out of range).
Simulation buildScene(const SceneConfig& scene);

}  // namespace cloth_sim::node
