// GraspFrames and SimClock on a tf2 buffer filled by hand: no master, no listener.
#include <cmath>
#include <string>

#include <gtest/gtest.h>
#include <tf2/buffer_core.h>

#include "cloth_sim/node/grasp_frames.h"
#include "cloth_sim/node/sim_clock.h"
#include "error_of.h"
#include "tf_fixture.h"

namespace cloth_sim::node {
namespace {

geometry_msgs::TransformStamped gripperAt(const Vec3& t, double stamp, double yaw = 0.0) {
  return transform("world", "gripper", t, yaw, stamp);
}

class GraspFramesTest : public ::testing::Test {
 protected:
  tf2::BufferCore buffer_{ros::Duration(10.0)};
  GraspFrames frames_{buffer_, "world", 0.5};
};

TEST_F(GraspFramesTest, InterpolatesBetweenTransformsAndAppliesTheOffset) {
  buffer_.setTransform(gripperAt(Vec3(0, 0, 1), 10.0), "test");
  buffer_.setTransform(gripperAt(Vec3(1, 0, 1), 11.0, M_PI / 2), "test");
  const Vec3 offset(0.1, 0, 0);
  frames_.add(3, "gripper", offset, Pose::Identity());
  const Pose p = frames_.poseAt(3, ros::Time(10.5));
  EXPECT_NEAR(p.translation().x(), 0.5 + 0.1 * std::cos(M_PI / 4), 1e-9);
  EXPECT_NEAR(p.translation().y(), 0.1 * std::sin(M_PI / 4), 1e-9);
  EXPECT_FALSE(frames_.find(3)->stale);
  // The same through lookup(), as a grasp request uses it.
  EXPECT_TRUE(frames_.lookup("gripper", offset, ros::Time(10.5)).isApprox(p));
}

TEST_F(GraspFramesTest, AFrameThatStopsHoldsItsLastPoseAndTurnsStale) {
  buffer_.setTransform(gripperAt(Vec3(0, 0, 1), 10.0), "test");
  buffer_.setTransform(gripperAt(Vec3(0, 0, 2), 11.0), "test");
  frames_.add(0, "gripper", Vec3::Zero(), Pose::Identity());
  EXPECT_NEAR(frames_.poseAt(0, ros::Time(11.2)).translation().z(), 2.0, 1e-12);
  EXPECT_FALSE(frames_.find(0)->stale);  // 0.2 s behind: within the timeout
  EXPECT_NEAR(frames_.poseAt(0, ros::Time(12.0)).translation().z(), 2.0, 1e-12);
  EXPECT_TRUE(frames_.find(0)->stale);
  ASSERT_EQ(frames_.staleFrames().size(), 1u);
  EXPECT_EQ(frames_.staleFrames()[0], "'gripper' (grasp 0)");
  buffer_.setTransform(gripperAt(Vec3(0, 0, 3), 12.0), "test");  // it comes back
  frames_.poseAt(0, ros::Time(12.0));
  EXPECT_FALSE(frames_.find(0)->stale);
}

TEST_F(GraspFramesTest, BeforeTheBufferTheOldestPoseIsHeldNeverALaterOne) {
  // A 12 s trajectory published at once into a 10 s buffer: its first 2 s are dropped. Asked
  // at 1 s, the frame must not jump to the newest pose (12 m away) but hold the oldest kept.
  for (int k = 0; k <= 120; ++k) buffer_.setTransform(gripperAt(Vec3(0.1 * k, 0, 1), 1.0 + 0.1 * k), "test");
  frames_.add(0, "gripper", Vec3::Zero(), Pose::Identity());
  const Pose early = frames_.poseAt(0, ros::Time(2.0));
  EXPECT_GE(early.translation().x(), 1.95);  // the oldest kept: about 3 s, x = 2 m
  EXPECT_LE(early.translation().x(), 2.15);
  EXPECT_TRUE(frames_.find(0)->before_buffer);
  EXPECT_FALSE(frames_.find(0)->stale);
  EXPECT_NEAR(frames_.poseAt(0, ros::Time(5.05)).translation().x(), 4.05, 1e-9);  // covered
  EXPECT_FALSE(frames_.find(0)->before_buffer);
  const FrameSample late = sampleFrame(buffer_, "world", "gripper", ros::Time(20.0));
  EXPECT_TRUE(late.after_buffer);
  EXPECT_NEAR(late.transform.transform.translation.x, 12.0, 1e-9);
}

TEST_F(GraspFramesTest, RefusesUnknownFramesAndBadOffsets) {
  EXPECT_EQ(test::errorOf([&] { frames_.lookup("nowhere", Vec3::Zero(), ros::Time(1)); }),
            "frame_id 'nowhere' is unknown to tf2 (no transform into 'world' has been published)");
  EXPECT_EQ(test::errorOf([&] { frames_.lookup("", Vec3::Zero(), ros::Time(1)); }),
            "frame_id is empty: name the tf frame to follow");
  buffer_.setTransform(gripperAt(Vec3(0, 0, 1), 10.0), "test");
  EXPECT_EQ(test::errorOf([&] { frames_.lookup("gripper", Vec3(NAN, 0, 0), ros::Time(1)); }),
            "offset is not finite");
  EXPECT_TRUE(frames_.lookup("world", Vec3(1, 2, 3), ros::Time(1))
                  .translation()
                  .isApprox(Vec3(1, 2, 3)));
}

TEST(SimClock, StampsGoOnAcrossAReset) {
  SimClock clock(ros::Time(100, 0));
  EXPECT_EQ(clock.stamp(0.5), ros::Time(100, 500000000));
  clock.restart(2.0);
  EXPECT_EQ(clock.stamp(0.0), ros::Time(102, 0));
  EXPECT_EQ(clock.stamp(0.25), ros::Time(102, 250000000));
  clock.anchor(ros::Time(200, 0), 0.5);  // following the ROS time: the frame ends now
  EXPECT_EQ(clock.stamp(0.5), ros::Time(200, 0));
  EXPECT_EQ(clock.stamp(0.25), ros::Time(199, 750000000));
}

TEST(SimClock, AJumpInSimulatedTimeNeverTakesTheStampsBack) {
  SimClock clock(ros::Time(1, 0));
  clock.jump(5.0, 2.0);  // a snapshot of t = 2 s restored at t = 5 s: stamps go on from 6 s
  EXPECT_EQ(clock.stamp(2.0), ros::Time(6, 0));
  clock.jump(2.0, 100.0);  // set to t = 100 s: later than the stamp reached, so forward to it
  EXPECT_EQ(clock.stamp(100.0), ros::Time(100, 0));
  EXPECT_GE(clock.stamp(100.0), ros::Time(6, 0));
}

TEST(StateDigest, EqualForEqualStatesAndChangesWithOneBit) {
  State a = State::atRest(Points::Random(3, 20));
  State b = a;
  EXPECT_EQ(stateDigest(a), stateDigest(b));
  EXPECT_EQ(stateDigest(a).size(), 16u);
  b.velocities(1, 7) = std::nextafter(b.velocities(1, 7), 1.0);
  EXPECT_NE(stateDigest(a), stateDigest(b));
}

}  // namespace
}  // namespace cloth_sim::node
