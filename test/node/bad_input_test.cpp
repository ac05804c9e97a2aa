// Bad input to a running cloth_sim_node: every refusal says why, topic refusals are logged
// (throttled), nothing changes and the node keeps publishing. Bad parameters stop the node
// with a message naming the parameter.

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include <cloth_sim/AddPin.h>
#include <cloth_sim/PinMove.h>
#include <cloth_sim/RemovePin.h>
#include <cloth_sim/RemoveSphere.h>
#include <cloth_sim/SpawnSphere.h>
#include <std_srvs/Trigger.h>

#include "ros_test_util.h"

namespace cloth_sim::test {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

NodeProbe& probe() {
  static NodeProbe p{ros::NodeHandle()};
  static const bool ready = p.waitForTraffic(60.0);
  EXPECT_TRUE(ready) << "no cloth/state or cloth/markers within 60 s";
  return p;
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

/// A refused request: success false, no id, and a message containing @p why.
template <class Response>
void expectRefused(const Response& res, const std::string& why) {
  EXPECT_FALSE(res.success) << why;
  EXPECT_EQ(res.id, -1) << why;
  EXPECT_TRUE(contains(res.message, why))
      << "expected '" << why << "', got '" << res.message << "'";
}

SpawnSphere::Request sphere(const geometry_msgs::PointStamped& center, double radius) {
  SpawnSphere::Request r;
  r.center = center;
  r.radius = radius;
  return r;
}

TEST(BadInput, SpawnSphereRefusesWhatItCannotUse) {
  probe();
  const auto ok = stamped("world", 0.0, 0.0, 1.0);
  std::vector<std::pair<SpawnSphere::Request, std::string>> cases = {
      {sphere(ok, 0.0), "sphere radius 0 must be in (0, 1e+06] m"},
      {sphere(ok, -0.1), "sphere radius -0.1 must be in (0, 1e+06] m"},
      {sphere(ok, kNaN), "radius nan m"},
      {sphere(stamped("world", kNaN, 0.0, 1.0), 0.1), "center (nan, 0, 1) is not finite"},
      {sphere(stamped("nowhere", 0.0, 0.0, 1.0), 0.1), "center: frame 'nowhere' is unknown"},
      {sphere(stamped("world", 100.0, 0.0, 1.0), 0.1), "beyond ~sphere_cull_distance"},
  };
  SpawnSphere::Request r = sphere(ok, 0.1);
  r.mass = -1.0;
  cases.emplace_back(r, "sphere mass -1 must be in [0, 1e+09] kg (0 = kinematic)");
  r.mass = 2.0;
  r.restitution = 1.5;
  cases.emplace_back(r, "sphere restitution 1.5 must be in [0, 1]");
  r.restitution = 0.0;
  r.mass = 0.0;
  r.velocity.x = kInf;
  cases.emplace_back(r, "velocity (inf, 0, 0) is not finite");
  r.velocity.x = 0.0;
  r.friction = -1.0;
  cases.emplace_back(r, "sphere friction -1 must be in [0, 100]");
  // Absurd but finite spheres were once answered success and then wrecked the scene.
  r.friction = 0.0;
  cases.emplace_back(sphere(ok, 1e6), "radius 1e+06 m must be at most the cloth's size, 1 m");
  r.velocity.y = 1e9;
  cases.emplace_back(r, "its speed 1e+09 m/s must be at most its radius per implicit step");
  r.velocity.y = 0.0;
  r.mass = 1e6;
  cases.emplace_back(r, "mass 1e+06 kg must be at most 100 times the cloth's mass");
  r.mass = 1e-300;
  cases.emplace_back(r, "must be 0 (kinematic) or at least 1e-09 times the cloth's mass");
  for (const auto& [req, why] : cases) {
    const auto res = call<SpawnSphere>(names::kSpawnSphere, req);
    expectRefused(res, why);
  }
  // A refused service call is logged too.
  EXPECT_TRUE(probe().waitForLog(
      std::string(names::kSpawnSphere) + ": sphere radius 0 must be in (0, 1e+06] m", 5.0));
}

TEST(BadInput, RemoveSphereAndRemovePinRefuseUnknownIds) {
  probe();
  RemoveSphere::Request rs;
  rs.id = 42;
  const auto sphere_res = call<RemoveSphere>(names::kRemoveSphere, rs);
  EXPECT_FALSE(sphere_res.success);
  EXPECT_TRUE(contains(sphere_res.message, "no sphere with id 42")) << sphere_res.message;
  RemovePin::Request rp;
  rp.id = 99;
  const auto pin_res = call<RemovePin>(names::kRemovePin, rp);
  EXPECT_FALSE(pin_res.success);
  EXPECT_TRUE(contains(pin_res.message, "no pin with id 99")) << pin_res.message;
}

TEST(BadInput, AddPinRefusesWhatItCannotUse) {
  probe();
  auto request = [](int vertex, const geometry_msgs::PointStamped& point, double stiffness) {
    AddPin::Request r;
    r.vertex = vertex;
    r.point = point;
    r.stiffness = stiffness;
    return r;
  };
  const auto origin = stamped("world", 0.0, 0.0, 1.0);
  const std::vector<std::pair<AddPin::Request, std::string>> cases = {
      {request(1024, origin, 0.0), "vertex 1024 is out of range [0, 1024)"},
      {request(-2, origin, 0.0), "vertex -2 is out of range [0, 1024)"},
      {request(-1, stamped("world", kNaN, 0.0, 0.0), 0.0), "point (nan, 0, 0) is not finite"},
      {request(-1, stamped("nowhere", 0.0, 0.0, 0.0), 0.0), "point: frame 'nowhere' is unknown"},
      {request(0, origin, 0.0), "vertex 0 is already pinned (pin 0)"},
      {request(5, origin, -5.0), "pin stiffness -5"},
      {request(5, origin, kNaN), "pin stiffness nan"},
  };
  for (const auto& [req, why] : cases) {
    const auto res = call<AddPin>(names::kAddPin, req);
    expectRefused(res, why);
  }
}

TEST(BadInput, PinMoveRefusalsAreLoggedThrottledPerKind) {
  NodeProbe& p = probe();
  ros::NodeHandle nh;
  ros::Publisher pub = nh.advertise<PinMove>(names::kPinMove, 100);
  ASSERT_TRUE(waitForSubscriber(pub));

  auto send = [&](int id, const geometry_msgs::PointStamped& target) {
    PinMove m;
    m.id = id;
    m.target = target;
    pub.publish(m);
  };
  send(99, stamped("world", 0.0, 0.0, 1.0));
  send(0, stamped("world", kNaN, 0.0, 1.0));
  send(0, stamped("nowhere", 0.0, 0.0, 1.0));
  send(0, stamped("world", 1e6, 0.0, 1.0));  // once accepted, then 30 rollbacks and a reset
  EXPECT_TRUE(p.waitForLog(std::string(names::kPinMove) + ": pin 99: no pin with id 99", 5.0));
  EXPECT_TRUE(
      p.waitForLog(std::string(names::kPinMove) + ": pin 0: target (1e+06, 0, 1) m is", 5.0));
  EXPECT_TRUE(p.waitForLog("beyond ~sphere_cull_distance = 20 m", 5.0));
  EXPECT_TRUE(p.waitForLog(
      std::string(names::kPinMove) + ": pin 0: target (nan, 0, 1) is not finite", 5.0));
  EXPECT_TRUE(p.waitForLog(
      std::string(names::kPinMove) + ": pin 0: target: frame 'nowhere' is unknown", 5.0));

  // The same refusal again and again within the throttle period is logged once.
  for (int i = 0; i < 20; ++i) {
    send(99, stamped("world", 0.0, 0.0, 1.0));
    ros::WallDuration(0.02).sleep();
  }
  ros::WallDuration(1.0).sleep();
  EXPECT_EQ(p.countLogs(std::string(names::kPinMove) + ": pin 99: no pin with id 99"), 1);
}

TEST(BadInput, NothingChangedAndTheNodeKeepsPublishing) {
  NodeProbe& p = probe();
  const Simulation initial =
      makeSimulation(loadSceneFile(sourcePath("config/scenes/hanging.yaml")));
  const std::size_t markers_before = p.markerCount();
  const auto states = p.collectStates(2.0);
  const double marker_rate = (p.markerCount() - markers_before) / 2.0;
  EXPECT_GT(marker_rate, 20.0);
  ASSERT_GT(states.size(), 60u);
  EXPECT_GT(states.back().sim_time, states.front().sim_time);
  for (const ClothState& s : states) {
    EXPECT_EQ(s.status, "ok");
    EXPECT_TRUE(s.spheres.empty());
    ASSERT_EQ(s.pins.size(), 2u);
    for (std::size_t k = 0; k < 2; ++k) {
      const Pin& pin = initial.pins().pins()[k];
      EXPECT_EQ(s.pins[k].id, pin.id);
      EXPECT_EQ(s.pins[k].vertex, pin.vertex);
      EXPECT_EQ(toVec3(s.pins[k].target), pin.target);
    }
  }
  for (const auto& a : p.collectMarkers(0.5)) EXPECT_TRUE(allFinite(a));
}

TEST(BadInput, EachResetIsLoggedOnce) {
  // Each reset once logged two lines (the service's answer and the reset itself).
  NodeProbe& p = probe();
  const std::string line = "reset to the initial state";
  const int before = p.countLogs(line);
  for (int k = 0; k < 3; ++k) {
    const auto res = call<std_srvs::Trigger>(names::kReset, std_srvs::Trigger::Request());
    EXPECT_TRUE(res.success) << res.message;
  }
  EXPECT_TRUE(p.waitForLog(std::string(names::kReset) + ": simulation " + line, 5.0));
  ros::WallDuration(1.0).sleep();  // /rosout is asynchronous: let every line arrive
  EXPECT_EQ(p.countLogs(line) - before, 3);
}

/// Runs cloth_sim_node with @p args against the test's master; returns its exit status and
/// output.
std::pair<int, std::string> runNode(const std::string& args) {
  return runNodeProcess(CLOTH_SIM_NODE_EXE, args, 60.0);
}

TEST(BadParameters, TheNodeStopsWithAMessageNamingTheParameter) {
  const std::pair<std::string, std::string> cases[] = {
      {"__name:=bad_params_1", "parameter '~scene': is required"},
      {"__name:=bad_params_2 _scene:=/nonexistent/scene.yaml",
       "parameter '~scene': /nonexistent/scene.yaml"},
      {"__name:=bad_params_3 _scene:=hanging _render_rate:=-5",
       "parameter '~render_rate': -5 must be in (0, 1000] Hz"},
      {"__name:=bad_params_4 _scene:=hanging _render_rate:=fast",
       "parameter '~render_rate': expected a number, got a string"},
      {"__name:=bad_params_5 _scene:=hanging _solver:=rk4",
       "parameter '~solver': unknown solver 'rk4'"},
  };
  for (const auto& [args, why] : cases) {
    const auto [status, output] = runNode(args);
    EXPECT_EQ(status, 1) << args << "\n" << output;
    EXPECT_TRUE(contains(output, why)) << args << ": expected '" << why << "' in:\n" << output;
  }
}

}  // namespace
}  // namespace cloth_sim::test

int main(int argc, char** argv) {
  return cloth_sim::test::runRosTests(argc, argv, "node_bad_input_test");
}
