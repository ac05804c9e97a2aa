// FrameInputs: a moved pin target goes there linearly across the frame's substeps, at most the
// speed limit per frame; a kinematic sphere's jump is a velocity for the frame (taken back out
// after it, or made at once by a rollback); grasp targets follow the pose source at each
// substep's time, at the substep's share of the speed limit; a hard pin stops where the
// cloth's self-contact pushes back. Pure: pins, colliders and grasps, no solver.
#include <gtest/gtest.h>

#include "cloth_sim/core/simulation/frame_inputs.h"

namespace cloth_sim {
namespace {

constexpr double kFrame = 1.0 / 60.0;  ///< s

/// Three particles on the x axis, 1 m apart, the frame inputs, pins, colliders and grasps.
class FrameInputsTest : public ::testing::Test {
 protected:
  FrameInputsTest() { x << 0, 1, 2, 0, 0, 0, 0, 0, 0; }
  /// Pins @p vertex where its particle is and starts every pin's target there.
  int pinParticle(int vertex) {
    const int id = pins.add(vertex, x.col(vertex), 0.0, 3);
    inputs.startPinsAt(pins, x);
    return id;
  }
  /// Pin @p id's target at substep @p k of @p n of the frame begun (no grasp).
  Vec3 targetAt(int id, int k, int n) {
    return inputs.pinsAt(k, n, 0.0, grasps, pins).find(id)->target;
  }

  Points x = Points(3, 3);
  PinSet pins;
  FrameInputs inputs;
  Colliders colliders;
  GraspSet grasps;
};

TEST_F(FrameInputsTest, WithNoMovedTargetTheSubstepsUseTheUsersPins) {
  pinParticle(0);
  inputs.beginFrame(pins, 10.0, kFrame, colliders);
  EXPECT_TRUE(inputs.paths().empty());
  for (int k = 1; k <= 4; ++k) EXPECT_EQ(&inputs.pinsAt(k, 4, k * kFrame / 4, grasps, pins), &pins);
}

TEST_F(FrameInputsTest, AMovedTargetGoesThereAFractionKOverNAtSubstepK) {
  const int id = pinParticle(0);
  const Vec3 from = x.col(0), to(0.3, -0.2, 0.1);
  pins.moveTarget(id, to);
  inputs.beginFrame(pins, 10.0, kFrame, colliders);
  ASSERT_EQ(inputs.paths().size(), 1u);
  for (int k = 1; k <= 4; ++k) {
    EXPECT_NE(&inputs.pinsAt(k, 4, 0.0, grasps, pins), &pins);
    EXPECT_EQ(targetAt(id, k, 4), Vec3(from + (k / 4.0) * (to - from))) << "substep " << k;
  }
  EXPECT_EQ(pins.find(id)->target, to);  // the user's pin is where the user put it
  inputs.endFrame(true, pins, grasps, kFrame, colliders);
  inputs.beginFrame(pins, 10.0, kFrame, colliders);  // reached: nothing moves in the next frame
  EXPECT_TRUE(inputs.paths().empty());
}

TEST_F(FrameInputsTest, AHardPinStopsWhereSelfContactPushesBack) {
  const int id = pinParticle(0);
  const Vec3 from = x.col(0), to(0.4, 0.0, -0.4);  // down and sideways
  pins.moveTarget(id, to);
  inputs.beginFrame(pins, 10.0, kFrame, colliders);
  Points push = Points::Zero(3, 3);
  EXPECT_EQ(inputs.pinsAt(1, 4, 0.0, grasps, pins, push).find(id)->target,
            Vec3(from + 0.25 * (to - from)));  // no push: as before
  push.col(0) = Vec3(0.0, 0.0, 5.0);  // the cloth below pushes its particle up (N)
  const Vec3 at = from + 0.25 * (to - from);
  for (int k = 2; k <= 4; ++k) {
    const Vec3 target = inputs.pinsAt(k, 4, 0.0, grasps, pins, push).find(id)->target;
    // It goes on sideways at the same pace, and no lower.
    EXPECT_NEAR(target.z(), at.z(), 1e-15) << "substep " << k;
    EXPECT_NEAR(target.x(), from.x() + (k / 4.0) * (to.x() - from.x()), 1e-15) << k;
  }
  EXPECT_EQ(pins.find(id)->target, to);  // the user's target stands ...
  inputs.endFrame(true, pins, grasps, kFrame, colliders);
  inputs.beginFrame(pins, 10.0, kFrame, colliders);  // ... and the next frame heads for it
  ASSERT_EQ(inputs.paths().size(), 1u);
  EXPECT_NEAR(inputs.paths()[0].from.z(), at.z(), 1e-15);
  EXPECT_EQ(inputs.paths()[0].to, to);
  push.col(0) = Vec3(0.0, 0.0, -5.0);  // pushed down, the way it goes: no stop
  EXPECT_EQ(inputs.pinsAt(4, 4, 0.0, grasps, pins, push).find(id)->target, to);
}

TEST_F(FrameInputsTest, ASoftPinIsNotStoppedBySelfContact) {
  const int id = pins.add(1, x.col(1), 50.0, 3);  // soft: its spring yields on its own
  inputs.startPinsAt(pins, x);
  const Vec3 to = Vec3(x.col(1)) + Vec3(0.0, 0.0, -0.1);
  pins.moveTarget(id, to);
  inputs.beginFrame(pins, 10.0, kFrame, colliders);
  Points push = Points::Zero(3, 3);
  push.col(1) = Vec3(0.0, 0.0, 5.0);
  EXPECT_EQ(inputs.pinsAt(4, 4, 0.0, grasps, pins, push).find(id)->target, to);
}

TEST_F(FrameInputsTest, AFarTargetIsReachedAtTheSpeedLimitOverSeveralFrames) {
  const int id = pinParticle(1);
  pins.moveTarget(id, Vec3(1.0, 5.0, 0.0));  // 5 m away, 2 m per frame
  for (const double reached : {2.0, 4.0, 5.0}) {
    inputs.beginFrame(pins, 2.0, kFrame, colliders);
    ASSERT_EQ(inputs.paths().size(), 1u);
    EXPECT_NEAR((targetAt(id, 3, 3) - Vec3(1.0, reached, 0.0)).norm(), 0.0, 1e-15);
    inputs.endFrame(true, pins, grasps, kFrame, colliders);
  }
  inputs.beginFrame(pins, 2.0, kFrame, colliders);
  EXPECT_TRUE(inputs.paths().empty());
}

TEST_F(FrameInputsTest, ANewPinIsApproachedFromItsParticle) {
  inputs.startPinsAt(pins, x);
  const int id = pins.add(2, Vec3(2.0, 0.0, 1.0), 0.0, 3);
  inputs.addPin(id, x.col(2));
  inputs.beginFrame(pins, 10.0, kFrame, colliders);
  ASSERT_EQ(inputs.paths().size(), 1u);
  EXPECT_EQ(targetAt(id, 1, 2), Vec3(2.0, 0.0, 0.5));
}

TEST_F(FrameInputsTest, AKinematicSphereJumpIsAVelocityForTheFrame) {
  const Vec3 c0(0.0, 0.0, 1.0), c1(0.3, 0.0, 1.0), v(0.0, 0.1, 0.0);
  const int id = colliders.addSphere(SphereCollider{-1, c0, 0.1, v});
  inputs.moveSphere(colliders, id, c1, v);
  EXPECT_EQ(colliders.findSphere(id)->center, c0);  // not yet: it sweeps there in the frame
  inputs.beginFrame(pins, 10.0, kFrame, colliders);
  EXPECT_NEAR((colliders.findSphere(id)->velocity - (v + (c1 - c0) / kFrame)).norm(), 0.0, 1e-12);
  inputs.endFrame(true, pins, grasps, kFrame, colliders);
  EXPECT_NEAR((colliders.findSphere(id)->velocity - v).norm(), 0.0, 1e-12);
  inputs.beginFrame(pins, 10.0, kFrame, colliders);  // the jump is spent
  EXPECT_NEAR((colliders.findSphere(id)->velocity - v).norm(), 0.0, 1e-12);
}

TEST_F(FrameInputsTest, ARolledBackFrameMakesTheSphereJumpAtOnce) {
  const Vec3 c0(0.0, 0.0, 1.0), c1(0.0, 0.2, 1.0);
  const int id = colliders.addSphere(SphereCollider{-1, c0, 0.1});
  inputs.moveSphere(colliders, id, c1, Vec3::Zero());
  const Colliders before = colliders;
  inputs.beginFrame(pins, 10.0, kFrame, colliders);
  colliders = before;  // the rollback
  inputs.endFrame(false, pins, grasps, kFrame, colliders);
  EXPECT_EQ(colliders.findSphere(id)->center, c1);
  EXPECT_EQ(colliders.findSphere(id)->velocity, Vec3::Zero());
}

TEST_F(FrameInputsTest, ADynamicBallIsPlacedAtOnce) {
  SphereCollider ball{-1, Vec3(0.0, 0.0, 1.0), 0.1};
  ball.mass = 0.5;
  const int id = colliders.addSphere(ball);
  inputs.moveSphere(colliders, id, Vec3(1.0, 0.0, 1.0), Vec3(0.0, 0.0, -1.0));
  EXPECT_EQ(colliders.findSphere(id)->center, Vec3(1.0, 0.0, 1.0));
  EXPECT_EQ(colliders.findSphere(id)->velocity, Vec3(0.0, 0.0, -1.0));
  EXPECT_THROW(inputs.moveSphere(colliders, id + 1, Vec3::Zero(), Vec3::Zero()),
               std::invalid_argument);
}

TEST_F(FrameInputsTest, GraspTargetsFollowThePoseSourceAtEachSubstepsTime) {
  const int own = pinParticle(0);
  grasps.add({2}, Pose::Identity(), x, pins);
  const int held = grasps.grasps()[0].pin_ids[0];
  grasps.setPoseSource([](int, double t) {
    return Pose(Eigen::Translation3d(0.0, 0.0, t) * Pose::Identity());  // rises at 1 m/s
  });
  inputs.startPinsAt(pins, x);
  pins.moveTarget(own, Vec3(0.0, 0.4, 0.0));  // a user's move too: the substeps get a copy
  inputs.beginFrame(pins, 10.0, kFrame, colliders);
  for (int k = 1; k <= 4; ++k) {
    const double t = k * kFrame / 4;
    const PinSet& at = inputs.pinsAt(k, 4, t, grasps, pins);
    EXPECT_EQ(at.find(held)->target, Vec3(2.0, 0.0, t)) << "substep " << k;
    EXPECT_EQ(pins.find(held)->target, Vec3(2.0, 0.0, t));
  }
  inputs.endFrame(true, pins, grasps, kFrame, colliders);
  // The held pin ends where its frame put it: the next frame sees no move of the user's.
  inputs.beginFrame(pins, 10.0, kFrame, colliders);
  EXPECT_TRUE(inputs.paths().empty());
}

TEST_F(FrameInputsTest, AGraspFrameThatJumpsIsFollowedAtTheSubstepsShareOfTheSpeedLimit) {
  grasps.add({2}, Pose::Identity(), x, pins);
  const Grasp& g = grasps.grasps()[0];
  grasps.setPoseSource([](int, double) { return Pose(Eigen::Translation3d(0.0, 0.0, -1.0)); });
  inputs.startPinsAt(pins, x);
  inputs.beginFrame(pins, 0.2, kFrame, colliders);
  for (int k = 1; k <= 4; ++k) {
    inputs.pinsAt(k, 4, k * kFrame / 4, grasps, pins);
    EXPECT_NEAR(pins.find(g.pin_ids[0])->target.z(), -0.05 * k, 1e-15) << "substep " << k;
  }
  inputs.endFrame(true, pins, grasps, kFrame, colliders);
  // Substeps 2 to 4 merged into one (past the frame deadline): the frame's 0.2 m all the same.
  inputs.beginFrame(pins, 0.2, kFrame, colliders);
  inputs.pinsAt(1, 4, 1.25 * kFrame, grasps, pins);
  EXPECT_NEAR(pins.find(g.pin_ids[0])->target.z(), -0.25, 1e-15);
  inputs.pinsAt(4, 4, 2 * kFrame, grasps, pins);
  EXPECT_NEAR(pins.find(g.pin_ids[0])->target.z(), -0.4, 1e-15);
  EXPECT_NEAR(g.lag, 0.6, 1e-15);
  inputs.endFrame(true, pins, grasps, kFrame, colliders);
  inputs.beginFrame(pins, 0.2, kFrame, colliders);
  EXPECT_TRUE(inputs.paths().empty());  // a grasp's lag is no user's move
}

}  // namespace
}  // namespace cloth_sim
