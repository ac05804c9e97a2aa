// Conversions between ROS messages and core types, no master.
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "cloth_sim/core/io/scene.h"
#include "cloth_sim/node/conversions.h"
#include "error_of.h"

namespace cloth_sim::node {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

using test::errorOf;

SpawnSphere::Request sphereRequest(double radius, double mass = 0.0, double friction = 0.0) {
  SpawnSphere::Request r;
  r.radius = radius;
  r.mass = mass;
  r.friction = friction;
  return r;
}

TEST(Conversions, PointsAndVectorsRoundTrip) {
  const Vec3 v(1.5, -2.25, 3.125);
  EXPECT_EQ(toVec3(toPointMsg(v)), v);
  EXPECT_EQ(toVec3(toVector3Msg(v)), v);
  EXPECT_EQ(toPointMsg(v).y, -2.25);
}

TEST(Conversions, RequireFiniteNamesTheValueAndWhatItIs) {
  EXPECT_EQ(errorOf([] { requireFinite(Vec3(1, 2, 3), "target"); }), "");
  const std::string e = errorOf([] { requireFinite(Vec3(kNaN, 0, 0), "target"); });
  EXPECT_NE(e.find("target (nan, 0, 0) is not finite"), std::string::npos) << e;
  EXPECT_NE(errorOf([] { requireFinite(Vec3(0, kInf, 0), "center"); }).find("center"),
            std::string::npos);
}

TEST(Conversions, AValidSphereRequestBecomesAKinematicSphere) {
  const SphereCollider s =
      sphereFromRequest(sphereRequest(0.2, 0.0, 0.4), Vec3(1, 2, 3), Vec3(0, 0, -1));
  EXPECT_EQ(s.center, Vec3(1, 2, 3));
  EXPECT_EQ(s.velocity, Vec3(0, 0, -1));
  EXPECT_EQ(s.radius, 0.2);
  EXPECT_EQ(s.friction, 0.4);
  EXPECT_FALSE(s.isDynamic());
}

TEST(Conversions, AMassiveSphereRequestBecomesADynamicSphere) {
  SpawnSphere::Request request = sphereRequest(0.1, 2.5, 0.2);
  request.restitution = 0.6;
  const SphereCollider s = sphereFromRequest(request, Vec3(0, 0, 1), Vec3(3, 0, 0));
  EXPECT_TRUE(s.isDynamic());
  EXPECT_EQ(s.mass, 2.5);
  EXPECT_EQ(s.restitution, 0.6);
  EXPECT_EQ(s.velocity, Vec3(3, 0, 0));
  const SphereInfo info = toSphereInfo(s);
  EXPECT_EQ(info.mass, 2.5);
  EXPECT_EQ(info.restitution, 0.6);
}

TEST(Conversions, EveryBadSphereRequestIsRefusedSayingWhy) {
  struct Case {
    SpawnSphere::Request request;
    Vec3 center, velocity;
    const char* reason;
  };
  const Vec3 o = Vec3::Zero();
  const Case cases[] = {
      {sphereRequest(0.0), o, o, "sphere radius 0 must be in (0, 1e+06] m"},
      {sphereRequest(-0.1), o, o, "sphere radius -0.1 must be in (0, 1e+06] m"},
      {sphereRequest(kNaN), o, o, "sphere radius nan must be in (0, 1e+06] m"},
      {sphereRequest(kInf), o, o, "sphere radius inf must be in (0, 1e+06] m"},
      {sphereRequest(0.1, -1.0), o, o, "sphere mass -1 must be in [0, 1e+09] kg (0 = kinematic)"},
      {sphereRequest(0.1, kNaN), o, o, "sphere mass nan must be in [0, 1e+09] kg"},
      {sphereRequest(0.1, 0.0, -0.5), o, o, "sphere friction -0.5 must be in [0, 100]"},
      // Through cloth/spawn_sphere FrameResolver refuses these first, naming the values.
      {sphereRequest(0.1), Vec3(kNaN, 0, 0), o, "sphere center must be finite"},
      {sphereRequest(0.1), o, Vec3(0, 0, kInf), "sphere velocity must be finite"},
  };
  SpawnSphere::Request bouncy = sphereRequest(0.1, 2.0);
  bouncy.restitution = 1.5;
  SpawnSphere::Request unknown_bounce = sphereRequest(0.1, 2.0);
  unknown_bounce.restitution = kNaN;
  const Case restitution_cases[] = {
      {bouncy, o, o, "sphere restitution 1.5 must be in [0, 1]"},
      {unknown_bounce, o, o, "sphere restitution nan must be in [0, 1]"}};
  std::vector<Case> all(std::begin(cases), std::end(cases));
  all.insert(all.end(), std::begin(restitution_cases), std::end(restitution_cases));
  for (const Case& c : all) {
    const std::string e = errorOf([&] { sphereFromRequest(c.request, c.center, c.velocity); });
    EXPECT_NE(e.find(c.reason), std::string::npos) << "expected '" << c.reason << "', got '" << e
                                                     << "'";
  }
}

TEST(Conversions, PinAndSphereInfo) {
  Pin pin;
  pin.id = 7;
  pin.vertex = 12;
  pin.target = Vec3(0.1, 0.2, 0.3);
  pin.stiffness = 50.0;
  const PinInfo p = toPinInfo(pin, Vec3(0.1, 0.2, 0.25));
  EXPECT_EQ(p.id, 7);
  EXPECT_EQ(p.vertex, 12);
  EXPECT_EQ(toVec3(p.target), pin.target);
  EXPECT_EQ(toVec3(p.position), Vec3(0.1, 0.2, 0.25));
  EXPECT_EQ(p.stiffness, 50.0);

  SphereCollider sphere;
  sphere.id = 3;
  sphere.center = Vec3(1, 1, 1);
  sphere.radius = 0.5;
  sphere.velocity = Vec3(2, 0, 0);
  sphere.friction = 0.3;
  const SphereInfo s = toSphereInfo(sphere);
  EXPECT_EQ(s.id, 3);
  EXPECT_EQ(toVec3(s.center), sphere.center);
  EXPECT_EQ(s.radius, 0.5);
  EXPECT_EQ(toVec3(s.velocity), sphere.velocity);
  EXPECT_EQ(s.friction, 0.3);
}

TEST(Conversions, ClothStateReportsTheStepAndTheSimulation) {
  Simulation sim = makeSimulation(
      loadSceneFile(std::string(CLOTH_SIM_SOURCE_DIR) + "/config/scenes/hanging.yaml"));
  SphereCollider sphere;
  sphere.center = Vec3(0, 0, 0.5);
  sphere.radius = 0.1;
  sim.addSphere(sphere);
  const StepReport report = sim.step();
  std_msgs::Header header;
  header.frame_id = "odom";
  header.stamp = ros::Time(12, 5);
  const ClothState s = toClothState(sim, report, StepCounters{4, 2, 1}, header);

  EXPECT_EQ(s.header.frame_id, "odom");
  EXPECT_EQ(s.header.stamp, ros::Time(12, 5));
  EXPECT_EQ(s.step, 4u);
  EXPECT_EQ(s.consecutive_failures, 2u);
  EXPECT_EQ(s.divergence_resets, 1u);
  EXPECT_NEAR(s.sim_time, sim.frameTime(), 1e-12);  // one frame of substeps
  EXPECT_EQ(s.time_step, sim.frameTime());
  EXPECT_EQ(s.substeps, sim.solverSettings().substeps);
  EXPECT_EQ(s.solver, "local_global");
  EXPECT_EQ(s.iterations, sim.solverSettings().max_iterations);
  EXPECT_EQ(s.convergence, report.convergence);
  EXPECT_EQ(s.max_strain, report.max_strain);
  EXPECT_EQ(s.error_estimate, report.error_estimate);
  EXPECT_EQ(s.carried_iteration_error, report.carried_iteration_error);
  EXPECT_GT(s.step_wall_time, 0.0);
  EXPECT_EQ(s.energy, sim.totalEnergy());
  EXPECT_EQ(s.status, "ok");
  EXPECT_EQ(s.message, "");
  ASSERT_EQ(s.pins.size(), 2u);
  for (const PinInfo& p : s.pins) {
    EXPECT_EQ(toVec3(p.position), sim.state().positions.col(p.vertex));
    EXPECT_EQ(toVec3(p.target), sim.pins().find(p.id)->target);
  }
  ASSERT_EQ(s.spheres.size(), 1u);
  EXPECT_EQ(toVec3(s.spheres[0].center), sim.colliders().spheres()[0].center);
  EXPECT_EQ(s.self_intersections, -1);  // self-collision off: not counted

  SelfContactSettings self;
  self.enabled = true;
  sim.setSelfContact(self);
  const StepReport counted = sim.step();
  EXPECT_EQ(toClothState(sim, counted, StepCounters{5, 0, 1}, header).self_intersections, 0);
}

TEST(Conversions, TheFrameStateQueueHoldsAStepCallWithinItsMemory) {
  // A 10 x 10 cloth: a whole call of 10000 frames (0.05 GB); 32 x 32: as many as 64 MB hold;
  // never under 10, however large the cloth.
  EXPECT_EQ(frameStateQueue(100, 10000), 10000u);
  const std::uint32_t q32 = frameStateQueue(1024, 10000);
  EXPECT_EQ(q32, static_cast<std::uint32_t>(std::floor(kFrameStateQueueBytes / (48.0 * 1024 + 256))));
  EXPECT_GT(q32, 1000u);
  EXPECT_LT(q32 * (48.0 * 1024), kFrameStateQueueBytes);
  EXPECT_EQ(frameStateQueue(10000000, 10000), 10u);
  EXPECT_EQ(frameStateQueue(100, 5), 10u);
}

}  // namespace
}  // namespace cloth_sim::node
