// Simulated time of cloth_sim_node: /clock, pause, unpause and stepping on request. A frame is
// always the same core step whoever triggers it (the timer or cloth/step), so a scripted run
// reproduces bit for bit (docs/ros_interface.md, "Simulated time").
#include <rosgraph_msgs/Clock.h>

#include "cloth_sim/node/cloth_sim_node.h"
#include "cloth_sim/node/names.h"

namespace cloth_sim::node {
namespace {

/// Frames one cloth/step call may ask for: at 60 Hz about 28 simulated hours, and a bound on
/// how long the single spinner thread is held.
constexpr std::uint32_t kMaxFramesPerCall = 6000000;

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
    return std::string(was ? "already paused" : "paused") + " at t = " +
           std::to_string(sim_.state().time) + " s";
  });
}

bool ClothSimNode::onUnpause(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
  return answer(names::kUnpause, res, [&] {
    const bool was = paused_;
    paused_ = false;
    return std::string(was ? "running" : "already running") + " from t = " +
           std::to_string(sim_.state().time) + " s";
  });
}

bool ClothSimNode::onStep(Step::Request& req, Step::Response& res) {
  answer(names::kStep, res, [&] {
    if (req.frames > kMaxFramesPerCall) {
      throw std::invalid_argument("frames " + std::to_string(req.frames) + " must be <= " +
                                  std::to_string(kMaxFramesPerCall) + " per call");
    }
    // Every frame publishes as the timer's do (state, wrenches, /clock), so a client sees the
    // same stream whether it steps or lets the node run.
    for (std::uint32_t k = 0; k < req.frames; ++k) stepFrame();
    return "stepped " + std::to_string(req.frames) + " frames to t = " +
           std::to_string(sim_.state().time) + " s" + (paused_ ? " (paused)" : "");
  });
  res.sim_time = sim_.state().time;
  res.stamp = simStamp();
  res.steps = steps_since_reset_;
  res.state_digest = stateDigest(sim_.state());
  return true;
}

}  // namespace cloth_sim::node
