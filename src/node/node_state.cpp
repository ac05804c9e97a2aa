// State snapshots of cloth_sim_node: cloth/get_state keeps everything the next frame depends on
// (the core's SimulationSnapshot and the node's frame tracking) and answers the readable state;
// cloth/set_state restores a kept snapshot bit for bit, or sets the particles; cloth/frame_state
// gives every frame's positions and velocities to a lockstep controller.
#include <geometry_msgs/WrenchStamped.h>

#include <cloth_sim/FrameState.h>

#include "cloth_sim/node/cloth_sim_node.h"
#include "cloth_sim/node/conversions.h"
#include "cloth_sim/node/names.h"

namespace cloth_sim::node {
namespace {

/// Snapshots cloth/get_state keeps; the oldest goes first (a snapshot holds a copy of the model).
constexpr std::size_t kMaxSnapshots = 64;

std::vector<double> flat(const Points& p) { return std::vector<double>(p.data(), p.data() + p.size()); }

/// @p values (3 per particle) as 3 x @p n points; throws naming @p what.
Points unflat(const std::vector<double>& values, int n, const char* what) {
  if (values.size() != 3u * static_cast<std::size_t>(n)) {
    throw std::invalid_argument(std::string(what) + ": " + std::to_string(values.size()) +
                                " numbers given, the cloth needs 3 x " + std::to_string(n));
  }
  return Eigen::Map<const Points>(values.data(), 3, n);
}

}  // namespace

bool ClothSimNode::onGetState(GetState::Request&, GetState::Response& res) {
  return answer(names::kGetState, res, [&] {
    if (snapshots_.size() >= kMaxSnapshots) snapshots_.erase(snapshots_.begin());
    res.snapshot_id = next_snapshot_++;
    snapshots_[res.snapshot_id] =
        NodeSnapshot{sim_.snapshot(), grasp_frames_.all(), body_frames_.all(), steps_since_reset_};
    res.sim_time = sim_.state().time;
    res.steps = steps_since_reset_;
    res.stamp = simStamp();
    res.positions = flat(sim_.state().positions);
    res.velocities = flat(sim_.state().velocities);
    std_msgs::Header header;
    header.stamp = res.stamp;
    header.frame_id = options_.frame_id;
    ClothState state = toClothState(sim_, last_report_, StepCounters{steps_since_reset_, 0, 0}, header);
    addGraspInfo(state);
    res.pins = state.pins;
    res.grasps = state.grasps;
    res.spheres = state.spheres;
    res.colliders = colliderInfos();
    res.state_digest = stateDigest(sim_.state());
    return "snapshot " + std::to_string(res.snapshot_id) + " kept at t = " +
           std::to_string(res.sim_time) + " s";
  });
}

bool ClothSimNode::onSetState(SetState::Request& req, SetState::Response& res) {
  answer(names::kSetState, res, [&] {
    const double t_before = sim_.state().time;
    std::string done;
    if (req.snapshot_id >= 0) {
      auto it = snapshots_.find(static_cast<std::uint32_t>(req.snapshot_id));
      if (it == snapshots_.end()) {
        throw std::invalid_argument("snapshot_id " + std::to_string(req.snapshot_id) +
                                    " is not kept (cloth/get_state keeps the last " +
                                    std::to_string(kMaxSnapshots) + ")");
      }
      sim_.restore(it->second.sim);
      grasp_frames_.restore(it->second.grasp_frames);
      body_frames_.restore(it->second.body_frames);
      steps_since_reset_ = it->second.steps;
      // A grasp made after the snapshot is gone, one released since is back: their topics follow.
      wrench_pubs_.clear();
      for (const Grasp& g : sim_.grasps()) {
        wrench_pubs_[g.id] = nh_.advertise<geometry_msgs::WrenchStamped>(names::graspWrench(g.id), 10);
      }
      done = "snapshot " + std::to_string(req.snapshot_id) + " restored";
    } else if (req.snapshot_id == -1) {
      const int n = sim_.model().particleCount();
      const Points x = unflat(req.positions, n, "positions");
      const Points v = req.velocities.empty() ? Points(Points::Zero(3, n))
                                              : unflat(req.velocities, n, "velocities");
      sim_.setState(x, v, req.sim_time);
      done = "positions and velocities set";
    } else {
      throw std::invalid_argument("snapshot_id " + std::to_string(req.snapshot_id) +
                                  " must be >= 0 (a kept snapshot) or -1 (the fields)");
    }
    // ROS time never goes back (tf2 buffers clear on a jump back): the stamps go on from here.
    clock_.jump(t_before, sim_.state().time);
    return done + " at t = " + std::to_string(sim_.state().time) + " s";
  });
  res.sim_time = sim_.state().time;
  res.state_digest = stateDigest(sim_.state());
  return true;
}

void ClothSimNode::publishFrameState() {
  if (frame_state_pub_.getNumSubscribers() == 0) return;  // a copy of every particle: on demand
  FrameState msg;
  msg.header.stamp = simStamp();
  msg.header.frame_id = options_.frame_id;
  msg.step = steps_since_reset_;
  msg.sim_time = sim_.state().time;
  msg.positions = flat(sim_.state().positions);
  msg.velocities = flat(sim_.state().velocities);
  msg.state_digest = stateDigest(sim_.state());
  frame_state_pub_.publish(msg);
}

}  // namespace cloth_sim::node
