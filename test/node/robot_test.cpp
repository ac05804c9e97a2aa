// The robot's side of cloth_sim_node through a real master (robot.test): a box on a tf frame
// pushed into a hanging sheet, snapshots restored bit for bit, a sphere moved, a 60 s trajectory
// published at once, the step action and its cancel, and a paused node that sleeps. The node
// publishes /clock and is paused: every test publishes its frames ahead in simulated time and
// steps, so nothing depends on the machine's speed.
#include <fstream>
#include <sstream>

#include <actionlib/client/simple_action_client.h>
#include <gtest/gtest.h>
#include <unistd.h>
#include <xmlrpcpp/XmlRpcClient.h>

#include <cloth_sim/AddCollider.h>
#include <cloth_sim/FrameState.h>
#include <cloth_sim/GetState.h>
#include <cloth_sim/MoveSphere.h>
#include <cloth_sim/RemoveCollider.h>
#include <cloth_sim/SetState.h>
#include <cloth_sim/SpawnSphere.h>
#include <cloth_sim/StepFramesAction.h>

#include "robot_util.h"

namespace cloth_sim::test {
namespace {

constexpr double kSubstep = 1.0 / 480.0;  // push.yaml: frames of 1/60 s in 8 substeps

AddCollider::Request boxOn(const std::string& frame, double side) {
  AddCollider::Request req;
  req.shape = "box";
  req.frame_id = frame;
  req.size.x = req.size.y = req.size.z = side;
  return req;
}

TEST(Robot, ABoxPushedIntoTheSheetLeavesNoParticleInsideAtAnyFrame) {
  const ros::Time origin = simOrigin();
  const double t0 = step(0).sim_time, speed = 1.0, side = 0.12;
  const Trajectory pusher = [&](double t) { return at(0.0, -0.2 + speed * (t - t0), 0.95); };
  publishAhead(origin, t0, t0 + 0.7, kSubstep, {{"pusher", pusher}});
  const AddCollider::Response added = call<AddCollider>(names::kAddCollider, boxOn("pusher", side));
  ASSERT_TRUE(added.success) << added.message;
  Collector<FrameState> frames(names::kFrameState);
  wallSleep(1.0);
  step(36);  // 0.6 s: the box's front 0.4 m along, 0.34 m past the sheet's plane
  ASSERT_TRUE(frames.waitForCount(36));
  double deepest = -INFINITY, farthest = -INFINITY;
  int checked = 0;
  for (const FrameState& f : frames.all()) {
    if (f.sim_time <= t0 + 1e-9) continue;
    const Vec3 center = pusher(f.sim_time).translation();  // the box where the frame ended
    for (std::size_t i = 0; i < f.positions.size(); i += 3) {
      const Vec3 p(f.positions[i], f.positions[i + 1], f.positions[i + 2]);
      const Vec3 q = (p - center).cwiseAbs() - Vec3::Constant(side / 2);
      const double inside = -(q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0));
      deepest = std::max(deepest, inside);
      farthest = std::max(farthest, p.y());
    }
    ++checked;
  }
  std::printf("[measured] box pushed at 1 m/s: %d frames, deepest particle %.4f m inside, cloth "
              "pushed to y = %.3f m\n", checked, deepest, farthest);
  EXPECT_EQ(checked, 36);
  EXPECT_LT(deepest, -0.005 + 1e-6);  // every particle at least the margin out, every frame
  EXPECT_GT(farthest, 0.3);           // the sheet went with the box (front at y = 0.46 m)
  RemoveCollider::Request remove;
  remove.id = added.id;
  EXPECT_TRUE(call<RemoveCollider>(names::kRemoveCollider, remove).success);
}

TEST(Robot, BadCollidersAreRefusedAndAMeshLoadsFromAPackage) {
  const std::size_t before = call<GetState>(names::kGetState, GetState::Request()).colliders.size();
  AddCollider::Request req = boxOn("nowhere", 0.1);
  AddCollider::Response res = call<AddCollider>(names::kAddCollider, req);
  EXPECT_FALSE(res.success);
  EXPECT_NE(res.message.find("frame_id 'nowhere' is unknown to tf2"), std::string::npos) << res.message;
  req = boxOn("world", 0.1);
  req.size.z = 0.0;
  res = call<AddCollider>(names::kAddCollider, req);
  EXPECT_FALSE(res.success);
  EXPECT_NE(res.message.find("box collider size 0 must be in (0, 1e+06] m"), std::string::npos) << res.message;
  req.shape = "cone";
  EXPECT_FALSE(call<AddCollider>(names::kAddCollider, req).success);
  req.shape = "mesh";
  req.mesh_file = "package://no_such_package/x.stl";
  res = call<AddCollider>(names::kAddCollider, req);
  EXPECT_FALSE(res.success);
  EXPECT_NE(res.message.find("no package 'no_such_package'"), std::string::npos) << res.message;
  RemoveCollider::Request remove;
  remove.id = 999;
  EXPECT_FALSE(call<RemoveCollider>(names::kRemoveCollider, remove).success);
  EXPECT_EQ(call<GetState>(names::kGetState, GetState::Request()).colliders.size(), before);
  // A still mesh from a package file, placed where its frame is now, far from the cloth.
  req.mesh_file = "package://cloth_sim/config/meshes/table.obj";
  req.still = true;
  req.origin.position.x = 5.0;
  res = call<AddCollider>(names::kAddCollider, req);
  ASSERT_TRUE(res.success) << res.message;
  remove.id = res.id;
  EXPECT_TRUE(call<RemoveCollider>(names::kRemoveCollider, remove).success);
}

std::vector<std::string> digestsOfNext(Collector<FrameState>& frames, std::uint32_t n) {
  frames.clear();
  step(n);
  EXPECT_TRUE(frames.waitForCount(n));
  std::vector<std::string> out;
  for (const FrameState& f : frames.all()) out.push_back(f.state_digest);
  return out;
}

TEST(Robot, ARestoredSnapshotContinuesBitForBit) {
  SpawnSphere::Request sphere;
  sphere.center = stamped("world", 0.0, -0.3, 0.9);
  sphere.radius = 0.08;
  sphere.velocity.y = 0.6;
  ASSERT_TRUE(call<SpawnSphere>(names::kSpawnSphere, sphere).success);
  AddCollider::Request still = boxOn("world", 0.1);
  still.origin.position.x = 0.15;
  still.origin.position.y = 0.1;
  still.origin.position.z = 0.9;
  still.friction = 0.5;
  ASSERT_TRUE(call<AddCollider>(names::kAddCollider, still).success);
  step(20);  // contacts under way: warm starts, BDF2-free implicit Euler history, the sphere
  Collector<FrameState> frames(names::kFrameState);
  wallSleep(1.0);
  const GetState::Response saved = call<GetState>(names::kGetState, GetState::Request());
  ASSERT_TRUE(saved.success) << saved.message;
  EXPECT_EQ(saved.positions.size(), 300u);
  EXPECT_EQ(saved.colliders.size(), 1u);
  EXPECT_EQ(saved.spheres.size(), 1u);
  const std::vector<std::string> first = digestsOfNext(frames, 40);
  SetState::Request back;
  back.snapshot_id = static_cast<int>(saved.snapshot_id);
  const SetState::Response restored = call<SetState>(names::kSetState, back);
  ASSERT_TRUE(restored.success) << restored.message;
  EXPECT_EQ(restored.state_digest, saved.state_digest);
  EXPECT_EQ(restored.sim_time, saved.sim_time);
  const std::vector<std::string> again = digestsOfNext(frames, 40);
  ASSERT_EQ(first.size(), again.size());
  int equal = 0;
  for (std::size_t k = 0; k < first.size(); ++k) equal += first[k] == again[k];
  std::printf("[measured] set_state then 40 frames: %d of 40 digests equal the original's\n", equal);
  EXPECT_EQ(equal, 40);
  // The fields alone: positions set, velocities zero; bad input refused, nothing changed.
  SetState::Request fields;
  fields.snapshot_id = -1;
  fields.positions = saved.positions;
  fields.sim_time = 7.0;
  const SetState::Response set = call<SetState>(names::kSetState, fields);
  EXPECT_TRUE(set.success) << set.message;
  EXPECT_DOUBLE_EQ(step(0).sim_time, 7.0);
  fields.positions.pop_back();
  const SetState::Response short_one = call<SetState>(names::kSetState, fields);
  EXPECT_FALSE(short_one.success);
  EXPECT_NE(short_one.message.find("positions: 299 numbers given"), std::string::npos);
  back.snapshot_id = 999;
  EXPECT_FALSE(call<SetState>(names::kSetState, back).success);
}

TEST(Robot, ASphereIsMovedAndAnUnknownOneRefused) {
  SpawnSphere::Request s;
  s.center = stamped("world", 1.0, 0.0, 0.5);
  s.radius = 0.05;
  const SpawnSphere::Response spawned = call<SpawnSphere>(names::kSpawnSphere, s);
  ASSERT_TRUE(spawned.success);
  MoveSphere::Request move;
  move.id = spawned.id;
  move.center = stamped("world", 1.2, 0.1, 0.5);
  move.velocity.z = 0.3;
  ASSERT_TRUE(call<MoveSphere>(names::kMoveSphere, move).success);
  step(1);
  const GetState::Response now = call<GetState>(names::kGetState, GetState::Request());
  const SphereInfo* got = nullptr;
  for (const SphereInfo& info : now.spheres) {
    if (info.id == spawned.id) got = &info;
  }
  ASSERT_NE(got, nullptr);
  // There across the frame, then on at its velocity: 1/60 s x 0.3 m/s above the target.
  EXPECT_NEAR(got->center.x, 1.2, 1e-9);
  EXPECT_NEAR(got->center.z, 0.5 + 0.3 / 60.0, 1e-9);
  EXPECT_NEAR(got->velocity.z, 0.3, 1e-12);
  move.id = 77;
  const MoveSphere::Response refused = call<MoveSphere>(names::kMoveSphere, move);
  EXPECT_FALSE(refused.success);
  EXPECT_EQ(refused.message, "no sphere with id 77");
}

TEST(Robot, ASixtySecondTrajectoryPublishedAtOnceIsFollowedFromItsStart) {
  const ros::Time origin = simOrigin();
  const double t0 = step(0).sim_time;
  const Trajectory orbit = [&](double t) {
    const double a = 0.5 * (t - t0);
    return at(1.5 + 0.3 * std::cos(a), 0.3 * std::sin(a), 1.0);
  };
  publishAhead(origin, t0, t0 + 60.0, 1.0 / 120.0, {{"orbit", orbit}});  // 7,201 poses
  AddCollider::Request req;
  req.shape = "sphere";
  req.radius = 0.03;
  req.frame_id = "orbit";
  const AddCollider::Response added = call<AddCollider>(names::kAddCollider, req);
  ASSERT_TRUE(added.success) << added.message;
  for (const double t : {1.0, 3.0}) {
    const Step::Response r = step(static_cast<std::uint32_t>(std::lround((t0 + t - step(0).sim_time) * 60)));
    const GetState::Response s = call<GetState>(names::kGetState, GetState::Request());
    for (const ColliderInfo& c : s.colliders) {
      if (c.id != added.id) continue;
      const Vec3 want = orbit(r.sim_time).translation();
      const double error = (toVec3(c.pose.position) - want).norm();
      std::printf("[measured] 60 s trajectory, at %.0f s: the collider is %.2g m from it\n", t, error);
      EXPECT_LT(error, 1e-6) << "at " << t << " s";
    }
  }
}

TEST(Robot, TheStepActionStepsAndIsCancelledAndStepIsCapped) {
  actionlib::SimpleActionClient<StepFramesAction> client(names::kStepFrames, true);
  ASSERT_TRUE(client.waitForServer(ros::Duration(20.0)));
  const double t0 = step(0).sim_time;
  StepFramesGoal goal;
  goal.frames = 120;
  client.sendGoal(goal);
  ASSERT_TRUE(client.waitForResult(ros::Duration(120.0)));
  EXPECT_EQ(client.getState(), actionlib::SimpleClientGoalState::SUCCEEDED);
  EXPECT_EQ(client.getResult()->frames_done, 120u);
  EXPECT_NEAR(client.getResult()->sim_time - t0, 2.0, 1e-9);
  goal.frames = 10000000;  // about 46 simulated hours: cancelled long before
  client.sendGoal(goal);
  wallSleep(1.0);
  client.cancelGoal();
  ASSERT_TRUE(client.waitForResult(ros::Duration(60.0)));
  EXPECT_EQ(client.getState(), actionlib::SimpleClientGoalState::PREEMPTED);
  EXPECT_GT(client.getResult()->frames_done, 0u);
  EXPECT_LT(client.getResult()->frames_done, 10000000u);
  Step::Request too_many;
  too_many.frames = 10001;
  const Step::Response refused = call<Step>(names::kStep, too_many);
  EXPECT_FALSE(refused.success);
  EXPECT_NE(refused.message.find("must be <= 10000 per call"), std::string::npos);
}

/// CPU seconds (user + system) process @p pid has used.
double cpuSeconds(int pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
  std::string line;
  std::getline(in, line);
  std::istringstream rest(line.substr(line.rfind(')') + 2));
  std::string field;
  double utime = 0, stime = 0;
  for (int k = 3; k <= 15 && rest >> field; ++k) {
    if (k == 14) utime = std::stod(field);
    if (k == 15) stime = std::stod(field);
  }
  return (utime + stime) / static_cast<double>(sysconf(_SC_CLK_TCK));
}

/// The node's process id, asked from the node itself (its getPid, as rosnode does).
int nodePid() {
  XmlRpc::XmlRpcValue args, result, payload;
  args[0] = ros::this_node::getName();
  args[1] = std::string("/") + names::kNode;
  if (!ros::master::execute("lookupNode", args, result, payload, true)) return -1;
  const std::string uri = payload;
  const std::size_t host_at = uri.find("//") + 2, port_at = uri.rfind(':');
  XmlRpc::XmlRpcClient client(uri.substr(host_at, port_at - host_at).c_str(),
                              std::stoi(uri.substr(port_at + 1)), "/");
  XmlRpc::XmlRpcValue pid_args, pid;
  pid_args[0] = ros::this_node::getName();
  if (!client.execute("getPid", pid_args, pid)) return -1;
  return static_cast<int>(pid[2]);
}

TEST(Robot, APausedNodeAtRealTimeFactorZeroSleeps) {
  const int pid = nodePid();
  ASSERT_GT(pid, 0);
  const double before = cpuSeconds(pid);
  wallSleep(3.0);  // paused (start_paused) at ~real_time_factor 0: nothing to do but render
  const double used = cpuSeconds(pid) - before;
  std::printf("[measured] paused node at real_time_factor 0: %.2f CPU s in 3 wall s\n", used);
  EXPECT_LT(used, 0.9);  // 30 %: it used a whole core (3 s) before
}

}  // namespace
}  // namespace cloth_sim::test

int main(int argc, char** argv) { return cloth_sim::test::runRosTests(argc, argv, "robot_test"); }
