// FrameResolver on a tf2 buffer filled by hand: no master, no listener.
#include <cmath>
#include <limits>
#include <string>

#include <gtest/gtest.h>

#include "cloth_sim/node/frame_resolver.h"
#include "error_of.h"
#include "tf_fixture.h"

namespace cloth_sim::node {
namespace {

geometry_msgs::PointStamped pointIn(const std::string& frame, const Vec3& p, double stamp = 0) {
  geometry_msgs::PointStamped s;
  s.header.frame_id = frame;
  s.header.stamp = ros::Time(stamp);
  s.point.x = p.x();
  s.point.y = p.y();
  s.point.z = p.z();
  return s;
}

/// world -> table: 1 m along x, 2 m along y, turned 90 degrees about z (static);
/// world -> arm: a dynamic frame known at t = 10 s only; 'island' is in another tree.
class FrameResolverTest : public ::testing::Test {
 protected:
  FrameResolverTest() : resolver_(buffer_, "world") {
    buffer_.setTransform(transform("world", "table", Vec3(1, 2, 0), M_PI / 2, 0), "test", true);
    buffer_.setTransform(transform("world", "arm", Vec3(0, 0, 1), 0, 10), "test", false);
    buffer_.setTransform(transform("elsewhere", "island", Vec3(0, 0, 0), 0, 0), "test", true);
  }

  std::string errorOf(const geometry_msgs::PointStamped& p) const {
    return test::errorOf([&] { resolver_.point(p, "target"); });
  }

  tf2_ros::Buffer buffer_;
  FrameResolver resolver_;
};

TEST_F(FrameResolverTest, TransformsAPointFromAnotherFrame) {
  // (1, 0, 0) in table: turned to (0, 1, 0), then moved by (1, 2, 0).
  EXPECT_TRUE(resolver_.point(pointIn("table", Vec3(1, 0, 0)), "target")
                  .isApprox(Vec3(1, 3, 0), 1e-12));
}

TEST_F(FrameResolverTest, RotatesAVectorWithoutMovingIt) {
  std_msgs::Header header;
  header.frame_id = "table";
  geometry_msgs::Vector3 v;
  v.x = 2.0;
  EXPECT_TRUE(resolver_.vector(header, v, "velocity").isApprox(Vec3(0, 2, 0), 1e-12));
}

TEST_F(FrameResolverTest, TheTargetFrameAnEmptyFrameAndALeadingSlashNeedNoTransform) {
  for (const char* frame : {"world", "", "/world"}) {
    EXPECT_EQ(resolver_.point(pointIn(frame, Vec3(4, 5, 6)), "target"), Vec3(4, 5, 6)) << frame;
  }
  EXPECT_EQ(resolver_.targetFrame(), "world");
}

TEST_F(FrameResolverTest, AStampTheBufferDoesNotHaveFallsBackToTheLatestTransform) {
  EXPECT_EQ(resolver_.point(pointIn("arm", Vec3(0, 0, 0), 25.0), "target"), Vec3(0, 0, 1));
  EXPECT_EQ(resolver_.point(pointIn("arm", Vec3(0, 0, 0), 0.0), "target"), Vec3(0, 0, 1));
}

TEST_F(FrameResolverTest, AnUnknownFrameIsRefusedByName) {
  const std::string e = errorOf(pointIn("nowhere", Vec3(0, 0, 0)));
  EXPECT_NE(e.find("target: frame 'nowhere' is unknown to tf2"), std::string::npos) << e;
}

TEST_F(FrameResolverTest, AHugeFrameNameIsNotEchoedBackWhole) {
  const std::string e = errorOf(pointIn(std::string(100000, 'x'), Vec3(0, 0, 0)));
  EXPECT_LT(e.size(), 300u) << e.substr(0, 300);
  EXPECT_NE(e.find("(100000 characters) is unknown to tf2"), std::string::npos) << e.substr(0, 300);
}

TEST_F(FrameResolverTest, AFrameWithNoPathToTheTargetIsRefused) {
  const std::string e = errorOf(pointIn("island", Vec3(0, 0, 0)));
  EXPECT_NE(e.find("frame 'island' cannot be transformed into 'world'"), std::string::npos) << e;
}

TEST_F(FrameResolverTest, ANonFiniteInputIsRefusedEvenInTheTargetFrame) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(errorOf(pointIn("world", Vec3(nan, 0, 0))).find("not finite"), std::string::npos);
  EXPECT_NE(errorOf(pointIn("table", Vec3(0, INFINITY, 0))).find("not finite"),
            std::string::npos);
}

}  // namespace
}  // namespace cloth_sim::node
