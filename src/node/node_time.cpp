// Simulated time of cloth_sim_node: /clock, pause, unpause and stepping on request. A frame is
// always the same core step whoever triggers it (the timer or cloth/step), so a scripted run
// reproduces bit for bit (docs/ros_interface.md, "Simulated time").
#include <rosgraph_msgs/Clock.h>

#include "cloth_sim/node/cloth_sim_node.h"
#include "cloth_sim/node/names.h"

namespace cloth_sim::node {
namespace {

/// Frames one goal of cloth/step_frames may ask for (about 19 simulated days at 60 Hz).
constexpr std::uint32_t kMaxActionFrames = 100000000;
/// Wall time (s) the action steps per tick before the other callbacks get the thread back.
constexpr double kActionChunk = 0.02;

}  // namespace

void ClothSimNode::publishClock() {
  if (!options_.publish_clock) return;
  rosgraph_msgs::Clock clock;
  clock.clock = simStamp();
  clock_pub_.publish(clock);
}

bool ClothSimNode::onPause(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
  return answer(names::kPause, res, [&] {
    const bool was = paused_;
    paused_ = true;
    step_timer_.stop();  // an idle node sleeps, whatever ~real_time_factor
    publishStateNow();   // latched: a client subscribing while paused gets this state
    return std::string(was ? "already paused" : "paused") + " at t = " +
           std::to_string(sim_.state().time) + " s";
  });
}

bool ClothSimNode::onUnpause(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
  return answer(names::kUnpause, res, [&] {
    const bool was = paused_;
    paused_ = false;
    step_timer_.start();
    return std::string(was ? "running" : "already running") + " from t = " +
           std::to_string(sim_.state().time) + " s";
  });
}

bool ClothSimNode::onStep(Step::Request& req, Step::Response& res) {
  try {
    if (req.frames > kMaxFramesPerCall) {
      throw std::invalid_argument("frames " + std::to_string(req.frames) + " must be <= " +
                                  std::to_string(kMaxFramesPerCall) +
                                  " per call (longer runs: the action " + names::kStepFrames + ")");
    }
    // Every frame publishes as the timer's do (state, wrenches, /clock), so a client sees the
    // same stream whether it steps or lets the node run.
    for (std::uint32_t k = 0; k < req.frames; ++k) stepFrame();
    res.success = true;
    res.message = "stepped " + std::to_string(req.frames) + " frames to t = " +
                  std::to_string(sim_.state().time) + " s" + (paused_ ? " (paused)" : "");
    ROS_DEBUG("%s: %s", names::kStep, res.message.c_str());  // a lockstep client calls it a lot
  } catch (const std::exception& e) {
    res.success = false;
    res.message = e.what();
    refuse(names::kStep, res.message);
  }
  res.sim_time = sim_.state().time;
  res.stamp = simStamp();
  res.steps = steps_since_reset_;
  res.state_digest = stateDigest(sim_.state());
  return true;
}

void ClothSimNode::onStepGoal() {
  const auto goal = step_action_->acceptNewGoal();
  if (goal->frames < 1 || goal->frames > kMaxActionFrames) {
    action_frames_done_ = 0;
    const StepFramesResult result = stepFramesResult(
        "frames " + std::to_string(goal->frames) + " must be in [1, " +
        std::to_string(kMaxActionFrames) + "]");
    step_action_->setAborted(result, result.message);
    return;
  }
  action_frames_left_ = goal->frames;
  action_frames_done_ = 0;
  step_action_timer_.start();
}

void ClothSimNode::onStepCancel() {
  const StepFramesResult result =
      stepFramesResult("cancelled after " + std::to_string(action_frames_done_) + " frames");
  action_frames_left_ = 0;
  step_action_timer_.stop();
  step_action_->setPreempted(result, result.message);
}

void ClothSimNode::stepActionTick(const ros::SteadyTimerEvent&) {
  if (!step_action_->isActive() || action_frames_left_ == 0) {
    step_action_timer_.stop();
    return;
  }
  // A chunk of frames, then the thread goes back to the other callbacks (a cancel among them).
  const ros::SteadyTime until = ros::SteadyTime::now() + ros::WallDuration(kActionChunk);
  do {
    stepFrame();
    --action_frames_left_;
    ++action_frames_done_;
  } while (action_frames_left_ > 0 && ros::SteadyTime::now() < until);
  StepFramesFeedback feedback;
  feedback.frames_done = action_frames_done_;
  feedback.sim_time = sim_.state().time;
  step_action_->publishFeedback(feedback);
  if (action_frames_left_ > 0) return;
  step_action_timer_.stop();
  const StepFramesResult result =
      stepFramesResult("stepped " + std::to_string(action_frames_done_) + " frames");
  step_action_->setSucceeded(result, result.message);
}

StepFramesResult ClothSimNode::stepFramesResult(const std::string& message) const {
  StepFramesResult result;
  result.frames_done = action_frames_done_;
  result.sim_time = sim_.state().time;
  result.stamp = simStamp();
  result.state_digest = stateDigest(sim_.state());
  result.message = message;
  return result;
}

}  // namespace cloth_sim::node
