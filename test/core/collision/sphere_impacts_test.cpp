#include <cmath>

#include <gtest/gtest.h>

#include "cloth_sim/core/collision/sphere_impacts.h"

namespace cloth_sim {
namespace {

const double kH = 1.0 / 240.0;

SphereCollider ball(const Vec3& c, const Vec3& v, double mass, double e = 0.0, double mu = 0.0) {
  SphereCollider s;
  s.center = c;
  s.radius = 0.1;
  s.velocity = v;
  s.mass = mass;
  s.restitution = e;
  s.friction = mu;
  return s;
}

/// Steps the spheres alone (no cloth) as Simulation does: advance under gravity, then impacts.
void run(Colliders& c, int steps, const Vec3& gravity) {
  for (int k = 0; k < steps; ++k) {
    c.advance(kH, gravity);
    resolveSphereImpacts(c, 2.0 * gravity.norm() * kH);
  }
}

TEST(SphereImpacts, ElasticHeadOnSwapsVelocities) {
  Colliders c;
  c.addSphere(ball(Vec3(-0.3, 0, 0), Vec3(2, 0, 0), 0.5, 1.0));
  c.addSphere(ball(Vec3(0.3, 0, 0), Vec3(-1, 0, 0), 0.5, 1.0));
  run(c, 120, Vec3::Zero());
  EXPECT_NEAR(c.spheres()[0].velocity.x(), -1.0, 1e-12);
  EXPECT_NEAR(c.spheres()[1].velocity.x(), 2.0, 1e-12);
}

TEST(SphereImpacts, PlasticImpactConservesMomentumAndLeavesACommonVelocity) {
  Colliders c;
  c.addSphere(ball(Vec3(-0.3, 0.02, 0), Vec3(3, 0, 0), 2.0));
  c.addSphere(ball(Vec3(0.3, 0, 0), Vec3(-1, 0, 0), 1.0));
  const Vec3 p0 = 2.0 * c.spheres()[0].velocity + 1.0 * c.spheres()[1].velocity;
  run(c, 120, Vec3::Zero());
  const Vec3 p1 = 2.0 * c.spheres()[0].velocity + 1.0 * c.spheres()[1].velocity;
  EXPECT_NEAR((p1 - p0).norm(), 0.0, 1e-12);
  // Head on with e = 0 they leave together at p / (m1 + m2).
  Colliders head_on;
  head_on.addSphere(ball(Vec3(-0.3, 0, 0), Vec3(3, 0, 0), 2.0));
  head_on.addSphere(ball(Vec3(0.3, 0, 0), Vec3(-1, 0, 0), 1.0));
  run(head_on, 120, Vec3::Zero());
  EXPECT_NEAR(head_on.spheres()[0].velocity.x(), 5.0 / 3.0, 1e-12);
  EXPECT_NEAR(head_on.spheres()[1].velocity.x(), 5.0 / 3.0, 1e-12);
}

TEST(SphereImpacts, SlidingBallEndsRollingAtFiveSevenths) {
  // Classic result for a solid ball thrown sliding without spin on a rough floor.
  Colliders c;
  c.setGround(GroundPlane{true, 0.0, 0.3});
  c.addSphere(ball(Vec3(0, 0, 0.1), Vec3(2.1, 0, 0), 0.4));
  run(c, 960, Vec3(0, 0, -9.81));  // 4 s; slipping stops after 2 v0 / (7 mu g) = 0.2 s
  const SphereCollider& s = c.spheres()[0];
  EXPECT_NEAR(s.velocity.x(), 2.1 * 5.0 / 7.0, 1e-6);
  EXPECT_NEAR(s.angular_velocity.y() * s.radius, s.velocity.x(), 1e-6);  // rolls: v = w_y r
  EXPECT_NEAR(s.center.z(), 0.1, 1e-12);
  EXPECT_NEAR(s.velocity.z(), 0.0, 1e-12);
}

TEST(SphereImpacts, RestitutionScalesTheBounceAndARestingBallStaysPut) {
  Colliders c;
  c.setGround(GroundPlane{true, 0.0, 0.0});
  c.addSphere(ball(Vec3(0, 0, 0.1 + 1e-9), Vec3(0, 0, -3.0), 1.0, 0.5));
  c.advance(kH, Vec3::Zero());
  resolveSphereImpacts(c, 0.0);
  EXPECT_NEAR(c.spheres()[0].velocity.z(), 1.5, 1e-9);
  Colliders rest;
  rest.setGround(GroundPlane{true, 0.0, 0.5});
  rest.addSphere(ball(Vec3(0, 0, 0.1), Vec3::Zero(), 1.0, 0.5));
  run(rest, 240, Vec3(0, 0, -9.81));
  EXPECT_NEAR(rest.spheres()[0].center.z(), 0.1, 1e-12);
  EXPECT_NEAR(rest.spheres()[0].velocity.norm(), 0.0, 1e-12);
}

TEST(SphereImpacts, KinematicSpheresPassThroughAndAreWallsForDynamicOnes) {
  Colliders c;
  c.addSphere(ball(Vec3(-0.3, 0, 0), Vec3(1, 0, 0), 0.0));
  c.addSphere(ball(Vec3(0.3, 0, 0), Vec3(-1, 0, 0), 0.0));
  run(c, 240, Vec3::Zero());
  EXPECT_NEAR(c.spheres()[0].velocity.x(), 1.0, 0.0);
  EXPECT_NEAR(c.spheres()[0].center.x(), 0.7, 1e-12);
  Colliders wall;
  wall.addSphere(ball(Vec3(0.5, 0, 0), Vec3::Zero(), 0.0));         // kinematic, still
  wall.addSphere(ball(Vec3(0.0, 0, 0), Vec3(2, 0, 0), 1.0, 0.8));  // dynamic, bounces off it
  run(wall, 120, Vec3::Zero());
  EXPECT_NEAR(wall.spheres()[1].velocity.x(), -1.6, 1e-9);
  EXPECT_EQ(wall.spheres()[0].center, Vec3(0.5, 0, 0));
}

TEST(SphereImpacts, RefusesBadSpheres) {
  Colliders c;
  SphereCollider s = ball(Vec3::Zero(), Vec3::Zero(), -1.0);
  EXPECT_THROW(c.addSphere(s), std::invalid_argument);
  s = ball(Vec3::Zero(), Vec3::Zero(), 1.0, 1.5);
  EXPECT_THROW(c.addSphere(s), std::invalid_argument);
  s = ball(Vec3::Zero(), Vec3::Zero(), 1.0);
  s.angular_velocity = Vec3(NAN, 0, 0);
  EXPECT_THROW(c.addSphere(s), std::invalid_argument);
  EXPECT_TRUE(c.spheres().empty());
}

}  // namespace
}  // namespace cloth_sim
