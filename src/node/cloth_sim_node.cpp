#include "cloth_sim/node/cloth_sim_node.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <rosgraph_msgs/Clock.h>
#include <sensor_msgs/PointCloud2.h>
#include <visualization_msgs/MarkerArray.h>

#include <cloth_sim/ClothState.h>
#include <cloth_sim/FrameState.h>

#include "cloth_sim/core/linalg/parallel.h"
#include "cloth_sim/core/model/strain_field.h"
#include "cloth_sim/node/body_messages.h"
#include "cloth_sim/node/conversions.h"
#include "cloth_sim/node/grasp_output.h"
#include "cloth_sim/node/names.h"
#include "cloth_sim/node/point_cloud.h"

namespace cloth_sim::node {
namespace {

constexpr double kDiagnosticsPoll = 0.25;  ///< s; the updater publishes every ~diagnostic_period
/// Frames kept in a row after which the reconfigured values count as stable (what a hold goes
/// back to): 2 s at 60 Hz.
constexpr int kStableFrames = 120;

/// How the markers look: ~strain_color_scale, ~shading, ~color_mode, and pins drawn with the
/// handles' scale but no wider than the particle spacing, so a pinned edge reads as a row of
/// beads, not a wall (trampoline, gravity_well).
MarkerStyle styleFor(const NodeOptions& options, const Simulation& sim, const SceneLimits& limits) {
  MarkerStyle style;
  style.strain_color_scale = options.strain_color_scale;
  style.shading = options.shading;
  style.color_mode = colorModeFromName(options.color_mode);  // checked by validateNodeOptions
  const auto& rest = sim.model().springs.rest_length;
  const double spacing = rest.empty() ? limits.size : *std::min_element(rest.begin(), rest.end());
  style.pin_diameter = std::min(0.4 * handleSizeFor(limits.size), 0.8 * spacing);
  return style;
}

}  // namespace

ClothSimNode::ClothSimNode(ros::NodeHandle nh, ros::NodeHandle pnh, NodeOptions options,
                           std::string scene_name, Simulation sim)
    : options_(std::move(options)),
      scene_name_(std::move(scene_name)),
      sim_(std::move(sim)),
      monitor_(sim_.frameTime(), options_.max_rollbacks),
      limits_(SceneLimits::of(sim_, options_.sphere_cull_distance)),
      budget_(frameBudgetFor(options_.budget_ms, sim_.frameTime(), "parameter '~budget_ms':")),
      style_(styleFor(options_, sim_, limits_)),
      ground_size_(std::max(3.0, 3.0 * limits_.size)),
      real_time_(ros::SteadyTime::now().toSec()),
      tf_buffer_(ros::Duration(options_.tf_buffer_duration)),
      tf_listener_(tf_buffer_),
      frames_(tf_buffer_, options_.frame_id),
      grasp_frames_(tf_buffer_, options_.frame_id, options_.grasp_frame_timeout),
      body_frames_(tf_buffer_, options_.frame_id, options_.grasp_frame_timeout),
      // With ~publish_clock the node owns ROS time (names::kSimTimeOriginSec says why not 0).
      clock_(options_.publish_clock ? ros::Time(names::kSimTimeOriginSec, 0) : ros::Time::now()),
      paused_(options_.start_paused),
      nh_(nh),
      pnh_(pnh),
      diagnostics_(nh, pnh) {
  sim_.setFrameDeadline(1e-3 * options_.frame_deadline_ms);  // checked by validateNodeOptions
  sim_.setPinSpeedLimit(limits_.pinSpeed());  // pins the cloth can follow
  stable_config_ = bridge_.current();
  advertiseTopics();
  advertiseServices();
  // Each substep asks where the grasp frames are at its own simulated time.
  sim_.setGraspPoseSource(
      [this](int id, double t) { return grasp_frames_.poseAt(id, clock_.stamp(t)); });
  // And where the bodies on frames are (the scene's, the robot's links, cloth/add_collider's).
  trackSceneBodies();
  sim_.setBodyPoseSource([this](int id, double t) { return bodyPoseAt(id, t); });
  publishClock();
  startDiagnostics();
  startReconfigure();
  startPinHandles();
  startTimers();
  publishStateNow();  // latched: a node started paused has a state to show
  ROS_INFO(
      "%s: scene '%s' (%d particles, %zu springs, %zu pins), solver %s with %d substeps of "
      "%d iterations, frame %.4f s, markers at %.1f Hz in frame '%s'",
      names::kNode, scene_name_.c_str(), sim_.model().particleCount(), sim_.model().springs.size(),
      sim_.pins().size(), sim_.solver().name(), sim_.solverSettings().substeps,
      sim_.solverSettings().max_iterations, sim_.frameTime(), options_.render_rate,
      options_.frame_id.c_str());
}

void ClothSimNode::advertiseTopics() {
  markers_pub_ = nh_.advertise<visualization_msgs::MarkerArray>(names::kMarkers, 2);
  // Latched: a client that subscribes while the node is paused gets the state now.
  state_pub_ = nh_.advertise<ClothState>(names::kState, 10, /*latch=*/true);
  points_pub_ = nh_.advertise<sensor_msgs::PointCloud2>(names::kPoints, 2);
  // A cloth/step call publishes its frames back to back: the queue holds a call's worth (as far
  // as memory allows), so that a subscriber that reads a little late still sees every frame.
  frame_state_pub_ = nh_.advertise<FrameState>(
      names::kFrameState, frameStateQueue(sim_.model().particleCount(), kMaxFramesPerCall));
  if (options_.publish_clock) {
    clock_pub_ = nh_.advertise<rosgraph_msgs::Clock>(names::kClock, 10, /*latch=*/true);
    if (!ros::Time::isSimTime()) {
      ROS_WARN("~publish_clock is true but /use_sim_time is not: this node and the others keep "
               "the wall time (set /use_sim_time true before the nodes start)");
    }
  }
  pin_move_sub_ = nh_.subscribe(names::kPinMove, 20, &ClothSimNode::onPinMove, this);
}

void ClothSimNode::advertiseServices() {
  services_ = {
      nh_.advertiseService(names::kSpawnSphere, &ClothSimNode::onSpawnSphere, this),
      nh_.advertiseService(names::kRemoveSphere, &ClothSimNode::onRemoveSphere, this),
      nh_.advertiseService(names::kAddPin, &ClothSimNode::onAddPin, this),
      nh_.advertiseService(names::kRemovePin, &ClothSimNode::onRemovePin, this),
      nh_.advertiseService(names::kReset, &ClothSimNode::onReset, this),
      nh_.advertiseService(names::kGrasp, &ClothSimNode::onGrasp, this),
      nh_.advertiseService(names::kRelease, &ClothSimNode::onRelease, this),
      nh_.advertiseService(names::kPause, &ClothSimNode::onPause, this),
      nh_.advertiseService(names::kUnpause, &ClothSimNode::onUnpause, this),
      nh_.advertiseService(names::kStep, &ClothSimNode::onStep, this),
      nh_.advertiseService(names::kAddCollider, &ClothSimNode::onAddCollider, this),
      nh_.advertiseService(names::kRemoveCollider, &ClothSimNode::onRemoveCollider, this),
      nh_.advertiseService(names::kMoveSphere, &ClothSimNode::onMoveSphere, this),
      nh_.advertiseService(names::kGetState, &ClothSimNode::onGetState, this),
      nh_.advertiseService(names::kSetState, &ClothSimNode::onSetState, this),
  };
  // Goals arrive on the global queue like every other callback: no thread of its own.
  step_action_ = std::make_unique<actionlib::SimpleActionServer<StepFramesAction>>(
      nh_, names::kStepFrames, /*auto_start=*/false);
  step_action_->registerGoalCallback([this] { onStepGoal(); });
  step_action_->registerPreemptCallback([this] { onStepCancel(); });
  step_action_->start();
}

void ClothSimNode::startDiagnostics() {
  diagnostics_.setHardwareID(names::kHardwareIdPrefix + scene_name_);
  diagnostics_.add(names::kDiagnosticsTask, this, &ClothSimNode::diagnose);
}

void ClothSimNode::startReconfigure() {
  // The scene (with ~solver / ~iterations) gives the initial values; the server then reports
  // them and calls back on every change.
  reconfigure_ =
      std::make_unique<dynamic_reconfigure::Server<ClothSimConfig>>(reconfigure_mutex_, pnh_);
  reconfigure_->updateConfig(bridge_.current());
  reconfigure_->setCallback(
      [this](ClothSimConfig& config, std::uint32_t level) { onReconfigure(config, level); });
}

void ClothSimNode::startPinHandles() {
  if (options_.max_interactive_pins <= 0) return;
  pin_handles_ = std::make_unique<PinHandles>(
      names::kPinHandles, options_.frame_id, options_.max_interactive_pins,
      [this](int id, const geometry_msgs::PointStamped& target) {
        movePin(names::kPinHandles, id, target);
      },
      handleSizeFor(limits_.size));
  pin_handles_->sync(sim_.pins().pins());
}

void ClothSimNode::startTimers() {
  // A frame per tick; at ~real_time_factor 0 the ticks come back to back (other callbacks still
  // run between them: one spinner thread, one queue).
  const double h = sim_.frameTime();
  const double period = options_.real_time_factor > 0.0 ? h / options_.real_time_factor : 1e-5;
  // Paused, the timer is stopped (cloth/unpause starts it): an idle node sleeps.
  step_timer_ = nh_.createSteadyTimer(ros::WallDuration(period), &ClothSimNode::step, this,
                                      /*oneshot=*/false, /*autostart=*/!paused_);
  step_action_timer_ = nh_.createSteadyTimer(ros::WallDuration(1e-4), &ClothSimNode::stepActionTick,
                                             this, false, /*autostart=*/false);
  render_timer_ = nh_.createSteadyTimer(ros::WallDuration(1.0 / options_.render_rate),
                                        &ClothSimNode::render, this);
  diagnostics_timer_ =
      nh_.createSteadyTimer(ros::WallDuration(kDiagnosticsPoll),
                            [this](const ros::SteadyTimerEvent&) { diagnostics_.update(); });
  if (options_.summary_period > 0.0) {
    summary_timer_ = nh_.createSteadyTimer(ros::WallDuration(options_.summary_period),
                                           &ClothSimNode::logSummary, this);
  }
}

void ClothSimNode::step(const ros::SteadyTimerEvent&) {
  if (!paused_) stepFrame();
}

void ClothSimNode::stepFrame() {
  if (!options_.publish_clock) clock_.anchor(ros::Time::now(), sim_.state().time + sim_.frameTime());
  last_report_ = sim_.step();
  ++steps_since_reset_;
  const bool rolled_back = last_report_.status != StepStatus::kOk;
  if (rolled_back) {
    warnThrottled("rolled back", "step: " + last_report_.message);
  } else {
    real_time_.add(sim_.frameTime());
  }
  if (last_report_.shortfall()) {
    char text[240];
    std::snprintf(text, sizeof text,
                  "frame cut at the %g ms ~frame_deadline_ms: %d substeps' iterations stopped, %d "
                  "substeps run as one (the settings ask for more than a frame can hold)",
                  options_.frame_deadline_ms, last_report_.cut_substeps,
                  last_report_.merged_substeps);
    warnThrottled("frame cut", text);
  }
  const bool must_reset =
      monitor_.record(rolled_back, last_report_.wall_time, last_report_.shortfall());
  // The same cause again (no input since the last automatic reset): held instead of a reset
  // loop, decided before the state goes out so that it never counts the reset it replaces.
  std::string held;
  if (must_reset && reset_since_input_) held = holdInputs();
  if (!held.empty()) {
    monitor_.holdInsteadOfReset();
    held_notice_ = "held: " + held + "; the cloth back to its initial shape (it led to an "
                   "automatic reset and again to " + std::to_string(options_.max_rollbacks) +
                   " rolled-back steps in a row; an input of yours lifts the hold)";
    warnThrottled("hold", held_notice_);
    if (reconfigure_) reconfigure_->updateConfig(bridge_.current());
  }

  std_msgs::Header header;
  header.stamp = simStamp();
  header.frame_id = options_.frame_id;
  if (state_pub_.getNumSubscribers() > 0) publishState(header);  // it costs an energy pass
  publishFrameState();
  warnFramesBeforeBuffer();
  publishWrenches(header.stamp);
  publishClock();
  if (!rolled_back) adaptSubsteps();

  kept_in_row_ = rolled_back ? 0 : kept_in_row_ + 1;
  if (kept_in_row_ >= kStableFrames) stable_config_ = bridge_.current();

  if (must_reset && held.empty()) {
    char why[160];
    std::snprintf(why, sizeof why,
                  "%d steps in a row were rolled back (~max_rollbacks); the solver '%s' and the "
                  "reconfigured values are kept",
                  options_.max_rollbacks, sim_.solver().name());
    resetSimulation(why, /*automatic=*/true);
    reset_since_input_ = true;
  }
  cullSpheres();
}

void ClothSimNode::publishState(const std_msgs::Header& header) {
  const StepCounters counters{steps_since_reset_, monitor_.consecutiveFailures(),
                              monitor_.divergenceResets()};
  ClothState state = toClothState(sim_, last_report_, counters, header);
  state.notice = held_notice_;
  if (!reconfigure_notice_.empty()) {
    state.notice += (state.notice.empty() ? "" : "; ") + reconfigure_notice_;
  }
  addGraspInfo(state);
  addColliderInfo(state);
  state_pub_.publish(state);
}

void ClothSimNode::publishStateNow() {
  std_msgs::Header header;
  header.stamp = simStamp();
  header.frame_id = options_.frame_id;
  publishState(header);
}

void ClothSimNode::adaptSubsteps() {
  if (!budget_) return;
  SolverSettings settings = sim_.solverSettings();
  if (settings.automaticSubsteps()) {
    // The error estimate chooses the substeps; the budget only bounds them (the reports say
    // when the tolerance needs more: StepReport::tolerance_unreachable).
    sim_.setSubstepLimit(budget_->next(sim_.substeps(), last_report_.wall_time));
    return;
  }
  const int chosen = budget_->next(settings.substeps, last_report_.wall_time);
  if (chosen == settings.substeps) return;
  settings.substeps = chosen;
  sim_.setSolverSettings(settings);  // a valid count (FrameBudget keeps to kSubsteps' range)
  ROS_INFO_THROTTLE(1.0, "~budget_ms %.2f: %d substeps per frame (one substep %.3f ms)",
                    1e3 * budget_->budget(), chosen, 1e3 * budget_->substepCost());
  if (reconfigure_) reconfigure_->updateConfig(bridge_.current());
}

void ClothSimNode::render(const ros::SteadyTimerEvent&) {
  if (pin_handles_) pin_handles_->sync(handledPins());
  if (points_pub_.getNumSubscribers() > 0) {  // built only for a subscriber
    std_msgs::Header header;
    header.stamp = simStamp();
    header.frame_id = options_.frame_id;
    points_pub_.publish(toPointCloud(sim_.state().positions, sim_.model().triangles, header,
                                     resolveThreads(sim_.solverSettings().threads)));
  }
  if (markers_pub_.getNumSubscribers() == 0) return;
  const double now = ros::SteadyTime::now().toSec();
  if (!pacer_.due(now)) return;  // a large cloth is sent less often (~marker_bandwidth)
  const Points& x = sim_.state().positions;
  const Eigen::VectorXd strain = vertexStrain(sim_.model(), x);
  // Static obstacles can be large: sent with the first array and then once a second.
  const auto per_second = static_cast<std::uint64_t>(std::max(1.0, std::round(options_.render_rate)));
  const bool with_obstacles = renders_++ % per_second == 0;
  const MarkerScene scene{x,
                          sim_.model().triangles,
                          strain,
                          sim_.pins().pins(),
                          sim_.colliders().spheres(),
                          sim_.colliders().ground(),
                          limits_.center,
                          ground_size_,
                          with_obstacles ? &sim_.colliders().meshes() : nullptr};
  std_msgs::Header header;
  header.stamp = ros::Time::now();
  header.frame_id = options_.frame_id;
  MarkerBuild build =
      buildMarkers(scene, style_, header, shown_, resolveThreads(sim_.solverSettings().threads));
  if (build.sanitized > 0) {
    refuse(names::kMarkers,
           std::to_string(build.sanitized) + " non-finite numbers in the state were drawn as 0");
  }
  shown_ = std::move(build.shown);
  appendGraspMarkers(sim_.grasps(), grasp_frames_, options_.force_arrow_scale, header,
                     shown_grasps_, build.markers);
  appendBodyMarkers(sim_.colliders().bodies().bodies(), header, shown_bodies_, build.markers);
  pacer_.sent(now, ros::serialization::serializationLength(build.markers));
  markers_pub_.publish(build.markers);
}

std::vector<Pin> ClothSimNode::handledPins() const {
  // A grasp's pins follow its frame: a handle on them would only be refused.
  std::vector<Pin> pins;
  for (const Pin& pin : sim_.pins().pins()) {
    if (!sim_.isGrasped(pin.id)) pins.push_back(pin);
  }
  return pins;
}

void ClothSimNode::resetSimulation(const std::string& why, bool automatic) {
  clock_.restart(sim_.state().time);  // ROS time goes on from here, never back
  // The automatic reset is a recovery: only the cloth restarts, the user's pins, grasps and
  // spheres stay (the README promises that bad input leaves the simulation as the user made it).
  if (automatic) {
    sim_.resetCloth();
  } else {
    sim_.reset();
    forgetGrasps();
    trackSceneBodies();  // the bodies added at run time are gone
  }
  steps_since_reset_ = 0;
  monitor_.clearFailures();
  // One line per reset: a requested one is logged by its service answer (onReset).
  if (automatic) {
    warnThrottled("automatic reset", "cloth reset to the initial shape of scene '" + scene_name_ +
                                         "', pins and spheres kept: " + why);
  }
}

void ClothSimNode::userInput() {
  reset_since_input_ = false;
  held_notice_.clear();
  kept_in_row_ = 0;  // stable means kStableFrames kept frames after the last input
}

std::string ClothSimNode::holdInputs() {
  std::string held;
  auto add = [&held](const std::string& what) { held += (held.empty() ? "" : ", ") + what; };
  ClothSimConfig config = stable_config_;
  for (const FieldOutcome& f : bridge_.apply(config)) {
    if (f.applied) add(f.field + " back to its last stable value");
  }
  // The cloth starts again from its initial shape, and nothing may pull it from there: each pin
  // whose target is away from its particle's initial position is held there, each moving
  // kinematic sphere stopped.
  clock_.restart(sim_.state().time);  // ROS time goes on from here, never back
  sim_.resetCloth();
  steps_since_reset_ = 0;
  monitor_.clearFailures();
  constexpr double kPull = 1e-3;  // m
  for (const Pin& pin : sim_.pins().pins()) {
    if (sim_.isGrasped(pin.id)) continue;
    const Vec3 rest = sim_.initialPositions().col(pin.vertex);
    if ((pin.target - rest).norm() <= kPull) continue;
    char text[200];
    std::snprintf(text, sizeof text, "pin %d's target (%.3g, %.3g, %.3g) m held at (%.3g, %.3g, %.3g) m",
                  pin.id, pin.target.x(), pin.target.y(), pin.target.z(), rest.x(), rest.y(),
                  rest.z());
    sim_.movePin(pin.id, rest);
    add(text);
  }
  std::vector<SphereCollider> moving;
  for (const SphereCollider& sphere : sim_.colliders().spheres()) {
    if (!sphere.isDynamic() && sphere.velocity.norm() > 0.0) moving.push_back(sphere);
  }
  for (const SphereCollider& sphere : moving) {
    sim_.moveSphere(sphere.id, sphere.center, Vec3::Zero());
    add("sphere " + std::to_string(sphere.id) + " stopped");
  }
  return held;
}

void ClothSimNode::cullSpheres() {
  std::vector<int> gone;
  for (const SphereCollider& s : sim_.colliders().spheres()) {
    if ((s.center - limits_.center).norm() > limits_.reach) gone.push_back(s.id);
  }
  for (int id : gone) {
    sim_.removeSphere(id);
    ROS_INFO("sphere %d removed: farther than ~sphere_cull_distance = %g m from the cloth", id,
             limits_.reach);
  }
}

void ClothSimNode::refuse(const std::string& where, const std::string& why) {
  const std::string text = where + ": " + why;
  warnThrottled(text, text);
}

void ClothSimNode::warnThrottled(const std::string& key, const std::string& text) {
  if (refusals_.allow(key, ros::WallTime::now().toSec())) ROS_WARN("%s", text.c_str());
}

void ClothSimNode::diagnose(diagnostic_updater::DiagnosticStatusWrapper& status) {
  DiagnosticsInput in;
  in.scene = scene_name_;
  in.solver = sim_.solver().name();
  in.substeps = sim_.solverSettings().substeps;
  in.iterations = sim_.solverSettings().max_iterations;
  in.error_tolerance = sim_.solverSettings().error_tolerance;
  in.error_estimate = last_report_.error_estimate;
  in.carried_iteration_error = last_report_.carried_iteration_error;
  in.tolerance_unreachable = last_report_.tolerance_unreachable;
  in.frame_budget = budget_ ? budget_->budget() : 0.0;
  in.window = monitor_.takeWindow();
  in.real_time_factor = real_time_.take(ros::SteadyTime::now().toSec());
  in.total_overruns = monitor_.totalOverruns();
  in.total_rollbacks = monitor_.totalRollbacks();
  in.consecutive_failures = monitor_.consecutiveFailures();
  in.divergence_resets = monitor_.divergenceResets();
  in.sim_time = sim_.state().time;
  in.pins = sim_.pins().size();
  in.spheres = sim_.colliders().spheres().size();
  in.grasps = sim_.grasps().size();
  in.paused = paused_;
  in.stale_grasp_frames = grasp_frames_.staleFrames();
  for (const Grasp& g : sim_.grasps()) {
    if (g.stopped) {
      in.stopped_grasps.emplace_back(g.id, g.lag);
    } else if (g.lag > 0.0) {
      in.lagging_grasps.emplace_back(g.id, g.lag);
    }
  }
  in.pin_speed = limits_.pinSpeed();
  in.frame_deadline = sim_.frameDeadline();
  in.notice = held_notice_;
  const DiagnosticsReport report = diagnosticsReport(in);
  status.summary(static_cast<std::uint8_t>(report.level), report.message);
  for (const auto& [key, value] : report.values) status.add(key, value);
}

void ClothSimNode::logSummary(const ros::SteadyTimerEvent&) {
  const StepReport& r = last_report_;
  ROS_INFO("t = %7.2f s | %s %d x %d it | frame %.2f ms of %.2f | max strain %.2f %% | energy %.4f J "
           "| pins %zu, spheres %zu | %s",
           sim_.state().time, sim_.solver().name(), r.substeps, r.iterations, 1e3 * r.wall_time,
           1e3 * sim_.frameTime(), 100.0 * r.max_strain, sim_.totalEnergy(),
           sim_.pins().size(), sim_.colliders().spheres().size(), stepStatusName(r.status));
}

void ClothSimNode::onReconfigure(ClothSimConfig& config, std::uint32_t /*level*/) {
  // A refused field is put back to the value in use, which the server then reports to every
  // client (the response of the request too), and cloth/state's notice says why until the next
  // request.
  std::string refused;
  for (const FieldOutcome& f : bridge_.apply(config)) {
    if (f.applied) userInput();
    if (f.applied) {
      ROS_INFO("%s: %s changed", names::kReconfigure, f.field.c_str());
    } else {
      refuse(std::string(names::kReconfigure) + " " + f.field, f.why);
      refused += (refused.empty() ? "" : "; ") + std::string(names::kReconfigure) + " " +
                 f.field + " refused, kept: " + f.why;
    }
  }
  reconfigure_notice_ = refused;
  if (state_pub_) publishStateNow();  // latched: seen at once, paused or not
}

}  // namespace cloth_sim::node
