#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "cloth_sim/core/collision/colliders.h"
#include "cloth_sim/core/io/scene.h"

namespace cloth_sim {
namespace {

const double kH = 1.0 / 60.0;

/// One particle moved from @p from to @p to in a step, then collided.
struct Contact {
  Points start, end, velocities;
  int hits = 0;
  Contact(Colliders c, const Vec3& from, const Vec3& to) : start(from), end(to) {
    velocities = (end - start) / kH;
    hits = resolveCollisions({kH, Eigen::VectorXd::Ones(1), {1}, start}, c, end, velocities);
  }
};

TEST(Colliders, GroundStopsAFallingParticleWithoutBounce) {
  Colliders c;
  c.setGround(GroundPlane{true, 0.0, 0.0});
  const Contact k(c, Vec3(0.2, 0.0, 0.01), Vec3(0.25, 0.0, -0.04));
  EXPECT_EQ(k.hits, 1);
  EXPECT_DOUBLE_EQ(k.end(2, 0), 0.0);
  EXPECT_DOUBLE_EQ(k.end(0, 0), 0.25);  // frictionless: the slide is kept
  // Velocity consistent with the projected position: no upward (energy-adding) component.
  EXPECT_NEAR((k.velocities.col(0) - (k.end.col(0) - k.start.col(0)) / kH).norm(), 0.0, 1e-12);
  EXPECT_LE(k.velocities(2, 0), 0.0);
}

TEST(Colliders, ParticleRestingOnTheGroundStaysAtRest) {
  // Gravity pulls it in every step; the response must cancel exactly that, adding nothing.
  Colliders c;
  c.setGround(GroundPlane{true, 0.5, 0.0});
  Points x = Points(Vec3(0.0, 0.0, 0.5)), v = Points::Zero(3, 1);
  for (int k = 0; k < 100; ++k) {
    const Points start = x;
    v.col(0) += kH * standardGravity();
    x += kH * v;
    resolveCollisions({kH, Eigen::VectorXd::Ones(1), {1}, start}, c, x, v);
    ASSERT_DOUBLE_EQ(x(2, 0), 0.5);
    ASSERT_EQ(v.col(0).norm(), 0.0);
  }
}

TEST(Colliders, GroundFrictionSticksOrSlowsTheSlide) {
  Colliders c;
  c.setGround(GroundPlane{true, 0.0, 1.0});
  // Penetration 0.05 m, slide 0.02 m < mu * 0.05: sticks.
  const Contact stick(c, Vec3(0, 0, 0), Vec3(0.02, 0, -0.05));
  EXPECT_NEAR(stick.end(0, 0), 0.0, 1e-15);
  // Penetration 0.01 m, slide 0.05 m: slides 0.05 - 1.0 * 0.01 = 0.04 m.
  const Contact slide(c, Vec3(0, 0, 0), Vec3(0.05, 0, -0.01));
  EXPECT_NEAR(slide.end(0, 0), 0.04, 1e-12);
}

TEST(Colliders, ParticleEndingInsideASphereIsPutOnItsSurface) {
  Colliders c;
  c.addSphere(SphereCollider{-1, Vec3(0, 0, 0), 0.5, Vec3::Zero(), 0.0});
  const Contact k(c, Vec3(0.1, 0.0, 0.7), Vec3(0.1, 0.0, 0.3));
  EXPECT_EQ(k.hits, 1);
  EXPECT_NEAR(k.end.col(0).norm(), 0.5, 1e-12);
  // Against a still sphere the contact takes energy away, never adds it.
  EXPECT_LE(k.velocities.col(0).norm(), ((Vec3(0.1, 0.0, 0.3) - Vec3(0.1, 0.0, 0.7)) / kH).norm());
  const Vec3 normal = k.end.col(0).normalized();
  EXPECT_LE(k.velocities.col(0).dot(normal), 1e-12);
}

TEST(Colliders, FastSphereDoesNotTunnelThroughAParticle) {
  // A 5 cm sphere thrown at 20 m/s moves 33 cm per step: without the swept test it would jump
  // over a particle at rest and leave it untouched behind it.
  Colliders c;
  c.addSphere(SphereCollider{-1, Vec3(0, 0, -0.2), 0.05, Vec3(0, 0, 20.0), 0.0});
  c.advance(kH);  // centre now at z = 0.1333, past the particle at z = 0
  const Contact k(c, Vec3(0.01, 0, 0), Vec3(0.01, 0, 0));
  EXPECT_EQ(k.hits, 1);
  const Vec3 center = c.spheres()[0].center;
  EXPECT_GT(k.end(2, 0), center.z());  // carried in front of the sphere
  EXPECT_NEAR((k.end.col(0) - center).norm(), 0.05, 1e-12);
}

TEST(Colliders, ParticlesOutsideAreUntouchedAndPinnedOnesSkipped) {
  Colliders c;
  c.addSphere(SphereCollider{-1, Vec3(0, 0, 0), 0.5, Vec3::Zero(), 0.0});
  c.setGround(GroundPlane{true, -1.0, 0.0});
  Points start(3, 2), end(3, 2);
  start << 0, 0, 0, 0, 0, 0;
  start.col(0) = Vec3(1, 1, 1);
  end.col(0) = Vec3(1, 1, 0.9);
  start.col(1) = Vec3(0, 0, 0.7);
  end.col(1) = Vec3(0, 0, 0.2);  // inside, but hard-pinned
  Points v = Points::Zero(3, 2);
  EXPECT_EQ(resolveCollisions({kH, Eigen::VectorXd::Ones(2), {1, 0}, start}, c, end, v), 0);
  EXPECT_EQ(end.col(1), Vec3(0, 0, 0.2));
}

TEST(Colliders, RefusesBadSpheresNamingTheField) {
  Colliders c;
  try {
    c.addSphere(SphereCollider{-1, Vec3::Zero(), 0.0, Vec3::Zero(), 0.0});
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("radius"), std::string::npos);
  }
  EXPECT_THROW(c.addSphere(SphereCollider{-1, Vec3(NAN, 0, 0), 1.0, Vec3::Zero(), 0.0}),
               std::invalid_argument);
  EXPECT_THROW(c.removeSphere(3), std::invalid_argument);
  EXPECT_TRUE(c.spheres().empty());
  const int id = c.addSphere(SphereCollider{-1, Vec3::Zero(), 1.0, Vec3::Zero(), 0.0});
  EXPECT_THROW(c.moveSphere(id, Vec3(0, 0, INFINITY), Vec3::Zero()), std::invalid_argument);
  EXPECT_EQ(c.findSphere(id)->center, Vec3::Zero());
}

TEST(DepenetrateStart, MovesAParticleOutOfAStillSphereAndItsHistoryByTheSameAmount) {
  Colliders c;
  c.addSphere(SphereCollider{-1, Vec3(0, 0, 1), 0.2, Vec3::Zero(), 0.0});
  Points x(3, 1), previous(3, 1);
  x.col(0) = Vec3(0.03, 0.04, 1.0);  // 5 cm from the centre, 15 cm inside
  previous.col(0) = Vec3(0.03, 0.04, 1.01);
  const Vec3 step = x.col(0) - previous.col(0);
  EXPECT_EQ(depenetrateStart(c, {1}, x, &previous), 1);
  EXPECT_NEAR((x.col(0) - Vec3(0, 0, 1)).norm(), 0.2, 1e-15);
  EXPECT_NEAR((x.col(0) - Vec3(0.12, 0.16, 1.0)).norm(), 0.0, 1e-15);  // radially out
  EXPECT_NEAR((x.col(0) - previous.col(0) - step).norm(), 0.0, 1e-15);  // the step's motion kept
}

TEST(DepenetrateStart, LiftsOntoTheGroundAndLeavesPinnedOutsideAndDynamicAlone) {
  Colliders c;
  c.setGround(GroundPlane{true, 0.0, 0.5});
  SphereCollider ball{-1, Vec3(5, 0, 1), 0.5, Vec3::Zero(), 0.0};
  ball.mass = 1.0;  // dynamic: its overlap is the solve's, which exchanges momentum
  c.addSphere(ball);
  Points x(3, 4);
  x.col(0) = Vec3(0.1, 0.2, -0.3);  // below the ground
  x.col(1) = Vec3(0.0, 0.0, -0.3);  // below, but hard-pinned
  x.col(2) = Vec3(1.0, 1.0, 0.5);   // outside everything
  x.col(3) = Vec3(5.0, 0.0, 1.1);   // inside the dynamic sphere
  const Points before = x;
  EXPECT_EQ(depenetrateStart(c, {1, 0, 1, 1}, x, nullptr), 1);
  EXPECT_EQ(x.col(0), Vec3(0.1, 0.2, 0.0));
  EXPECT_EQ(x.rightCols(3), before.rightCols(3));
}

/// A 0.2 m sheet lying still at z = 0, without gravity, after the ground was raised 5 cm under
/// it (as a live setting can) and one frame of 1/60 s.
Simulation sheetUnderARaisedGround(int substeps, const std::string& integrator) {
  Simulation sim = makeSimulation(parseScene(
      "time_step: 1/60\n"
      "gravity: [0, 0, 0]\n"
      "solver: {name: local_global, substeps: " + std::to_string(substeps) +
          ", iterations: 10, integrator: " + integrator + "}\n"
      "cloth: {grid: {rows: 5, cols: 5, size: [0.2, 0.2], position: [0, 0, 0]}}\n"
      "material: {areal_density: 0.2, springs: {structural: 1000, shear: 100}}\n"
      "colliders: {ground: {height: 0, friction: 0.5}}\n",
      "sheet_on_ground"));
  sim.step();  // a history for BDF2
  sim.setGround(GroundPlane{true, 0.05, 0.5});
  sim.step();
  return sim;
}

// An overlap the step starts with is moved out of, not driven out of: pushed out in the step,
// it would become the velocity depth / h (3 m/s at 1 substep, 384 m/s at 128) and the sheet
// would fly off the ground. Lifted without velocity, it rests there at any step.
TEST(DepenetrateStart, ASheetUnderARaisedGroundIsLiftedOntoItAtRestAtAnyStep) {
  for (const std::string integrator : {"implicit_euler", "bdf2"}) {
    for (int substeps : {1, 8, 128}) {
      const Simulation sim = sheetUnderARaisedGround(substeps, integrator);
      const State& s = sim.state();
      EXPECT_LT((s.positions.row(2).array() - 0.05).abs().maxCoeff(), 1e-12)
          << integrator << " " << substeps;
      EXPECT_LT(s.velocities.cwiseAbs().maxCoeff(), 1e-9) << integrator << " " << substeps;
    }
  }
}

}  // namespace
}  // namespace cloth_sim
