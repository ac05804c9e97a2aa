// cloth_sim_node through demo.launch with a real master: markers and state rates and content,
// a pin moved in another frame, spheres spawned (still, thrown, dynamic) and removed, reset.
#include <cmath>

#include <gtest/gtest.h>
#include <std_srvs/Trigger.h>

#include <visualization_msgs/InteractiveMarkerFeedback.h>
#include <visualization_msgs/InteractiveMarkerUpdate.h>

#include <atomic>
#include <mutex>

#include <diagnostic_msgs/DiagnosticArray.h>

#include <cloth_sim/AddPin.h>
#include <cloth_sim/PinMove.h>
#include <cloth_sim/RemoveSphere.h>
#include <cloth_sim/SpawnSphere.h>

#include "ros_test_util.h"

namespace cloth_sim::test {
namespace {

/// world -> test_frame. integration.test publishes test_frame -> world as a turn of 90 degrees
/// about z followed by a move of (0.2, -0.3, 0.4) m; this is its inverse.
Vec3 toTestFrame(const Vec3& w) {
  const Vec3 d = w - Vec3(0.2, -0.3, 0.4);
  return Vec3(d.y(), -d.x(), d.z());
}

constexpr double kRenderRate = 30.0;  // Hz, demo.launch's default
constexpr double kRateTolerance = 0.25;

/// The hanging scene as the node loaded it, for counts, triangles and rest positions.
struct Scene {
  Scene() : sim(makeSimulation(loadSceneFile(sourcePath("config/scenes/hanging.yaml")))) {}
  Simulation sim;
};
Scene& scene() {
  static Scene s;
  return s;
}

NodeProbe& probe() {
  static NodeProbe p{ros::NodeHandle()};
  static const bool ready = p.waitForTraffic(60.0);
  EXPECT_TRUE(ready) << "no cloth/state or cloth/markers within 60 s";
  return p;
}

void reset() {
  const auto res = call<std_srvs::Trigger>(names::kReset, std_srvs::Trigger::Request());
  ASSERT_TRUE(res.success) << res.message;
}

const PinInfo* findPin(const ClothState& s, int id) {
  for (const PinInfo& p : s.pins) {
    if (p.id == id) return &p;
  }
  return nullptr;
}

TEST(Integration, MarkersAndStateArriveAtTheirRatesWithTheWholeCloth) {
  NodeProbe& p = probe();
  const int n = scene().sim.model().particleCount();
  const Eigen::Matrix3Xi& triangles = scene().sim.model().triangles;
  const double window = 5.0;  // s
  const std::size_t markers_before = p.markerCount();
  const std::vector<ClothState> states = p.collectStates(window);
  const double marker_rate = (p.markerCount() - markers_before) / window;
  const double state_rate = states.size() / window;
  const double step_rate = 1.0 / scene().sim.frameTime();
  RecordProperty("marker_rate_hz", std::to_string(marker_rate));
  RecordProperty("state_rate_hz", std::to_string(state_rate));
  ASSERT_GE(states.size(), 2u);
  const double frame = scene().sim.frameTime();
  const double simulated = states.back().sim_time - states.front().sim_time;
  const double real_time_factor = simulated / window;
  std::printf("[measured] cloth/markers %.2f Hz (configured %.0f), cloth/state %.2f Hz "
              "(steps %.1f Hz), simulated %.2f s in %.1f s\n", marker_rate, kRenderRate,
              state_rate, step_rate, simulated, window);
  // One state per frame, whatever the machine's speed.
  EXPECT_NEAR(static_cast<double>(states.size()), simulated / frame + 1.0, 2.0);
  // The wall-clock rates hold when the node keeps real time; a machine too busy for that (the
  // node's own diagnostics say so) slows every timer, which is not this test's subject.
  if (real_time_factor >= 0.9) {
    EXPECT_NEAR(marker_rate, kRenderRate, kRateTolerance * kRenderRate);
    EXPECT_NEAR(state_rate, step_rate, kRateTolerance * step_rate);
  } else {
    std::printf("[measured] the machine was too busy for real time (%.2f simulated s per s): "
                "wall-clock rates not judged\n", real_time_factor);
  }

  const auto arrays = p.collectMarkers(1.0);
  ASSERT_GE(arrays.size(), 10u);
  for (const auto& a : arrays) {
    ASSERT_TRUE(allFinite(a));
    const visualization_msgs::Marker* cloth = findMarker(a, names::kClothNs, 0);
    ASSERT_NE(cloth, nullptr);
    EXPECT_EQ(cloth->header.frame_id, names::kDefaultFrame);
    EXPECT_EQ(cloth->type, visualization_msgs::Marker::TRIANGLE_LIST);
    EXPECT_EQ(cloth->colors.size(), cloth->points.size());
    const Points x = clothPositions(a, triangles, n);  // one position per particle
    EXPECT_TRUE(x.allFinite()) << "a particle of the scene is missing from the cloth marker";
    EXPECT_NE(findMarker(a, "pins", 0), nullptr);
    EXPECT_NE(findMarker(a, "pins", 1), nullptr);
    for (const auto& m : a.markers) {
      EXPECT_EQ(m.action, visualization_msgs::Marker::ADD) << "nothing was removed";
    }
  }
}

TEST(Integration, APinMovedInAnotherFrameBringsItsVertexToTheTarget) {
  NodeProbe& p = probe();
  reset();
  ros::NodeHandle nh;
  ros::Publisher pub = nh.advertise<PinMove>(names::kPinMove, 1);
  ASSERT_TRUE(waitForSubscriber(pub));
  const Vec3 goal(-0.3, 0.6, 1.6);  // world; pin 0 rests at (-0.5, 0.5, 1.5)
  const Vec3 local = toTestFrame(goal);
  PinMove move;
  move.id = 0;
  move.target = stamped("test_frame", local.x(), local.y(), local.z());
  const ros::WallTime sent = ros::WallTime::now();
  pub.publish(move);

  constexpr double kTolerance = 1e-3;  // m
  constexpr double kTime = 2.0;        // s
  const auto reached = p.waitForState(
      [&](const ClothState& s) {
        const PinInfo* pin = findPin(s, 0);
        return pin != nullptr && (toVec3(pin->position) - goal).norm() < kTolerance;
      },
      kTime);
  ASSERT_TRUE(reached) << "pin 0 did not reach " << goal.transpose() << " within " << kTime
                       << " s";
  const double latency = (ros::WallTime::now() - sent).toSec();
  const PinInfo* pin = findPin(*reached, 0);
  const double error = (toVec3(pin->position) - goal).norm();
  std::printf("[measured] pin 0 at %.2e m from its target, seen %.3f s after the move\n", error,
              latency);
  EXPECT_LT((toVec3(pin->target) - goal).norm(), 1e-9);

  const auto drawn = p.waitForMarkers(
      [&](const visualization_msgs::MarkerArray& a) {
        const auto* m = findMarker(a, "pins", 0);
        return m && (Vec3(m->pose.position.x, m->pose.position.y, m->pose.position.z) - goal)
                            .norm() < 1e-9;
      },
      2.0);
  EXPECT_TRUE(drawn) << "the pin marker did not move to the target";
}

TEST(Integration, DraggingAPinHandleMovesThePin) {
  NodeProbe& p = probe();
  reset();
  // What RViz sends while a person drags the handle of pin 1.
  ros::NodeHandle nh;
  ros::Publisher pub = nh.advertise<visualization_msgs::InteractiveMarkerFeedback>(
      std::string(names::kPinHandles) + "/feedback", 10);
  ASSERT_TRUE(waitForSubscriber(pub)) << "no drag handle server";
  const Vec3 goal(0.4, 0.3, 1.7);
  // What a second RViz hears: the handle's new pose.
  std::atomic<bool> seen_elsewhere{false};
  ros::Subscriber updates = nh.subscribe<visualization_msgs::InteractiveMarkerUpdate>(
      std::string(names::kPinHandles) + "/update", 10,
      [&](const visualization_msgs::InteractiveMarkerUpdateConstPtr& u) {
        for (const auto& pose : u->poses) {
          const Vec3 at(pose.pose.position.x, pose.pose.position.y, pose.pose.position.z);
          if (pose.name == "pin_1" && (at - goal).norm() < 1e-9) seen_elsewhere = true;
        }
      });
  const ros::WallTime connect_until = ros::WallTime::now() + ros::WallDuration(3.0);
  while (updates.getNumPublishers() == 0 && ros::WallTime::now() < connect_until) {
    ros::WallDuration(0.02).sleep();
  }
  visualization_msgs::InteractiveMarkerFeedback fb;
  fb.header.frame_id = "world";
  fb.client_id = "/rviz/InteractiveMarkers";
  fb.marker_name = "pin_1";
  fb.control_name = "move_xy";
  fb.event_type = visualization_msgs::InteractiveMarkerFeedback::POSE_UPDATE;
  fb.pose.position.x = goal.x();
  fb.pose.position.y = goal.y();
  fb.pose.position.z = goal.z();
  fb.pose.orientation.w = 1.0;
  pub.publish(fb);
  const auto moved = p.waitForState(
      [&](const ClothState& s) {
        const PinInfo* pin = findPin(s, 1);
        return pin != nullptr && (toVec3(pin->position) - goal).norm() < 1e-9;
      },
      3.0);
  EXPECT_TRUE(moved) << "pin 1 did not follow its handle";
  const ros::WallTime until = ros::WallTime::now() + ros::WallDuration(3.0);
  while (!seen_elsewhere && ros::WallTime::now() < until) ros::WallDuration(0.02).sleep();
  EXPECT_TRUE(seen_elsewhere) << "other RViz windows were not sent the dragged handle's pose";
}

TEST(Integration, ASpawnedSphereIsDrawnKeepsTheClothOutAndIsRemoved) {
  NodeProbe& p = probe();
  reset();
  const Vec3 center(0.0, 0.5, 1.0);  // world: in the plane the cloth swings down into
  const double radius = 0.15;
  const Vec3 local = toTestFrame(center);
  SpawnSphere::Request req;
  req.center = stamped("test_frame", local.x(), local.y(), local.z());
  req.radius = radius;
  const auto res = call<SpawnSphere>(names::kSpawnSphere, req);
  ASSERT_TRUE(res.success) << res.message;
  ASSERT_GE(res.id, 0);

  const auto states = p.collectSimulatedTime(1.5);
  int contacts = 0;
  for (const ClothState& s : states) contacts += s.contacts;
  EXPECT_GT(contacts, 0) << "the cloth never touched the sphere";

  const auto arrays = p.collectMarkers(1.5);
  ASSERT_GE(arrays.size(), 10u);
  double closest = INFINITY;
  for (const auto& a : arrays) {
    const auto* m = findMarker(a, "spheres", res.id);
    ASSERT_NE(m, nullptr) << "sphere " << res.id << " not drawn";
    EXPECT_EQ(m->type, visualization_msgs::Marker::SPHERE);
    EXPECT_NEAR(m->scale.x, 2.0 * radius, 1e-12);
    EXPECT_LT((Vec3(m->pose.position.x, m->pose.position.y, m->pose.position.z) - center).norm(),
              1e-9);
    const Points x = clothPositions(a, scene().sim.model().triangles,
                                    scene().sim.model().particleCount());
    closest = std::min(closest, (x.colwise() - center).colwise().norm().minCoeff());
  }
  std::printf("[measured] closest cloth particle to the sphere centre: %.6f m (radius %.3f)\n",
              closest, radius);
  EXPECT_GE(closest, radius * (1.0 - 1e-9)) << "a cloth particle is inside the sphere";
  EXPECT_LT(closest, radius + 0.02) << "the cloth is not even near the sphere";

  RemoveSphere::Request remove;
  remove.id = res.id;
  const auto removed = call<RemoveSphere>(names::kRemoveSphere, remove);
  ASSERT_TRUE(removed.success) << removed.message;
  const auto deleted = p.waitForMarkers(
      [&](const visualization_msgs::MarkerArray& a) {
        const auto* m = findMarker(a, "spheres", res.id);
        return m && m->action == visualization_msgs::Marker::DELETE;
      },
      2.0);
  EXPECT_TRUE(deleted) << "no DELETE for the removed sphere";
  for (const auto& a : p.collectMarkers(0.5)) {
    EXPECT_EQ(findMarker(a, "spheres", res.id), nullptr) << "removed sphere still sent";
  }
}

/// @p states from the first one that shows a sphere: a state published before the node handled
/// the spawn can open the window.
std::vector<ClothState> withSphere(std::vector<ClothState> states) {
  while (!states.empty() && states.front().spheres.empty()) states.erase(states.begin());
  return states;
}

TEST(Integration, AThrownKinematicSphereKeepsItsVelocityThroughTheCloth) {
  NodeProbe& p = probe();
  reset();
  ros::WallDuration(2.0).sleep();  // let the cloth swing down into the plane y = 0.5
  const Vec3 start(0.0, -0.3, 1.0), velocity(0.0, 1.5, 0.0);  // world
  const Vec3 local = toTestFrame(start);
  SpawnSphere::Request req;
  req.center = stamped("test_frame", local.x(), local.y(), local.z());
  req.velocity.x = velocity.y();  // the same velocity in test_frame (turned 90 degrees)
  req.velocity.y = -velocity.x();
  req.radius = 0.1;
  const auto res = call<SpawnSphere>(names::kSpawnSphere, req);
  ASSERT_TRUE(res.success) << res.message;

  const auto states = withSphere(p.collectStates(1.5));  // crosses y = 0.5 after about 0.5 s
  ASSERT_GE(states.size(), 20u);
  int contacts = 0;
  for (const ClothState& s : states) contacts += s.contacts;
  EXPECT_GT(contacts, 0) << "the cloth did not react to the sphere";
  const ClothState& first = states.front();
  const ClothState& last = states.back();
  ASSERT_EQ(first.spheres.size(), 1u);
  ASSERT_EQ(last.spheres.size(), 1u);
  EXPECT_LT((toVec3(last.spheres[0].velocity) - velocity).norm(), 1e-9);
  const Vec3 travelled = toVec3(last.spheres[0].center) - toVec3(first.spheres[0].center);
  const Vec3 expected = velocity * (last.sim_time - first.sim_time);
  EXPECT_LT((travelled - expected).norm(), 1e-9) << travelled.transpose();
  EXPECT_GT(last.spheres[0].center.y, 0.9) << "the sphere did not pass through";
}

TEST(Integration, AThrownDynamicSphereFallsAndIsSlowedByTheCloth) {
  NodeProbe& p = probe();
  reset();
  // Thrown down at the middle of the cloth, which has only started to fall (it is flat at
  // z = 1.5 at the reset): the ball meets it within a few frames, whatever the solver settings
  // (a cloth left to swing first is somewhere else at each configuration).
  const double mass = 0.2, speed = 4.0;  // kg, m/s
  SpawnSphere::Request req;
  req.center = stamped("world", 0.0, 0.0, 1.8);
  req.velocity.z = -speed;
  req.radius = 0.1;
  req.mass = mass;
  const auto res = call<SpawnSphere>(names::kSpawnSphere, req);
  ASSERT_TRUE(res.success) << res.message;

  const auto states = withSphere(p.collectSimulatedTime(0.8));
  ASSERT_GE(states.size(), 10u);
  int contacts = 0;
  double push = 0.0;  // m/s: how much slower than a free fall since the first state
  const ClothState& first = states.front();
  for (const ClothState& s : states) {
    contacts += s.contacts;
    ASSERT_EQ(s.spheres.size(), 1u);
    EXPECT_EQ(s.spheres[0].mass, mass);
    const double free_fall = first.spheres[0].velocity.z - 9.81 * (s.sim_time - first.sim_time);
    push = std::max(push, s.spheres[0].velocity.z - free_fall);
  }
  EXPECT_GT(contacts, 0) << "the sphere never touched the cloth";
  std::printf("[measured] dynamic sphere: up to %.3f m/s slower than a free fall\n", push);
  // The converged small-step run of this throw (64 substeps) ends 2.9 m/s above free fall;
  // the ball's drag alone accounts for 0.6 m/s of it.
  EXPECT_GT(push, 1.0) << "the cloth did not push back on the sphere";
  const ClothState& last = states.back();
  const double dt = last.sim_time - first.sim_time;
  // Gravity acts on it: by the end it falls faster than it was thrown.
  EXPECT_LT(last.spheres[0].velocity.z, -speed - 0.25 * 9.81 * dt);

  // Its marker follows it.
  const auto arrays = p.collectMarkers(0.3);
  ASSERT_GE(arrays.size(), 3u);
  const auto* early = findMarker(arrays.front(), "spheres", res.id);
  const auto* late = findMarker(arrays.back(), "spheres", res.id);
  ASSERT_NE(early, nullptr);
  ASSERT_NE(late, nullptr);
  EXPECT_LT(late->pose.position.z, early->pose.position.z - 0.05) << "the marker does not fall";
}

TEST(Integration, TheDiagnosticsJudgeEachFrameAgainstTheFramesBudget) {
  // A frame of 1/60 s is many substeps (32 in hanging): real time means a frame within
  // 16.67 ms, not a substep within its own h.
  probe();
  ros::NodeHandle nh;
  std::mutex mutex;
  std::string message;
  ros::Subscriber diag = nh.subscribe<diagnostic_msgs::DiagnosticArray>(
      names::kDiagnostics, 10, [&](const diagnostic_msgs::DiagnosticArray::ConstPtr& a) {
        std::lock_guard<std::mutex> lock(mutex);
        for (const auto& s : a->status)
          if (s.name.find(names::kDiagnosticsTask) != std::string::npos) message = s.message;
      });
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(5.0);
  while (ros::WallTime::now() < end) {
    {
      std::lock_guard<std::mutex> lock(mutex);
      if (!message.empty()) break;
    }
    ros::WallDuration(0.05).sleep();
  }
  std::lock_guard<std::mutex> lock(mutex);
  ASSERT_FALSE(message.empty()) << "no simulation step status on /diagnostics";
  EXPECT_NE(message.find("16.67 ms budget"), std::string::npos) << message;
}

TEST(Integration, ResetRestoresTheInitialState) {
  NodeProbe& p = probe();
  reset();
  // Edit everything a user can: pin a vertex found by a point in another frame, move a pin,
  // spawn a sphere.
  const Vec3 rest16 = scene().sim.state().positions.col(16);  // top edge, between the pins
  const Vec3 near16 = toTestFrame(rest16);
  AddPin::Request add;
  add.vertex = -1;
  add.point = stamped("test_frame", near16.x(), near16.y(), near16.z());
  const auto added = call<AddPin>(names::kAddPin, add);
  ASSERT_TRUE(added.success) << added.message;
  EXPECT_EQ(added.vertex, 16);
  SpawnSphere::Request spawn;
  spawn.center = stamped("world", 0.0, 0.3, 1.0);
  spawn.radius = 0.1;
  const auto sphere = call<SpawnSphere>(names::kSpawnSphere, spawn);
  ASSERT_TRUE(sphere.success) << sphere.message;
  ros::WallDuration(2.0).sleep();
  const ClothState edited = p.latestState();
  ASSERT_EQ(edited.pins.size(), 3u);
  ASSERT_EQ(edited.spheres.size(), 1u);
  ASSERT_GT(edited.sim_time, 1.0);

  reset();
  // The first drawing after the reset, and a state from after it: its sim time bounds how far
  // the cloth may have fallen from rest since the reset.
  const ros::Time reset_done = ros::Time::now();
  const auto after = p.waitForMarkers(
      [&](const visualization_msgs::MarkerArray& a) {
        return !a.markers.empty() && a.markers[0].header.stamp > reset_done;
      },
      2.0);
  ASSERT_TRUE(after);
  const ros::Time drawn = after->markers[0].header.stamp;
  const auto state = p.waitForState([&](const ClothState& c) { return c.header.stamp > drawn; },
                                    2.0);
  ASSERT_TRUE(state);
  const ClothState& s = *state;
  const double g = 9.81, t = s.sim_time;
  ASSERT_LT(t, 0.2) << "the simulation time did not restart";
  const auto& initial = scene().sim;
  ASSERT_EQ(s.pins.size(), initial.pins().size());
  for (const Pin& pin : initial.pins().pins()) {
    const PinInfo* got = findPin(s, pin.id);
    ASSERT_NE(got, nullptr) << "pin " << pin.id;
    EXPECT_LT((toVec3(got->target) - pin.target).norm(), 1e-12);
    EXPECT_EQ(got->vertex, pin.vertex);
  }
  EXPECT_TRUE(s.spheres.empty());
  const Points x = clothPositions(*after, initial.model().triangles,
                                  initial.model().particleCount());
  const double moved = (x - initial.state().positions).colwise().norm().maxCoeff();
  EXPECT_LE(moved, 0.5 * g * t * t + 1e-3) << "the cloth is not back at rest (t = " << t << ")";
  const auto* sphere_marker = findMarker(*after, "spheres", sphere.id);
  EXPECT_TRUE(sphere_marker == nullptr ||
              sphere_marker->action == visualization_msgs::Marker::DELETE);
}

}  // namespace
}  // namespace cloth_sim::test

int main(int argc, char** argv) {
  return cloth_sim::test::runRosTests(argc, argv, "node_integration_test");
}
