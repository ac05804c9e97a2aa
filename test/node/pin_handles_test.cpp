// The drag handle of a pin, as a message (no master, no server).
#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "cloth_sim/node/pin_handles.h"

namespace cloth_sim::node {
namespace {

using visualization_msgs::InteractiveMarkerControl;

/// The control's local x axis in the marker frame.
Vec3 axisOf(const InteractiveMarkerControl& c) {
  const Eigen::Quaterniond q(c.orientation.w, c.orientation.x, c.orientation.y, c.orientation.z);
  return q.normalized() * Vec3::UnitX();
}

TEST(PinHandleName, RoundTripsAndRejectsOtherNames) {
  EXPECT_EQ(pinHandleName(12), "pin_12");
  EXPECT_EQ(pinIdFromHandleName("pin_12"), 12);
  EXPECT_EQ(pinIdFromHandleName("pin_0"), 0);
  for (const char* bad : {"pin_", "pin_x", "pin_3a", "pin_-1", "sphere_3", "", "pin"}) {
    EXPECT_EQ(pinIdFromHandleName(bad), -1) << bad;
  }
}

TEST(PinHandle, FreeAxisAndPlaneDragsAtTheTarget) {
  const auto m = makePinHandle(4, Vec3(0.5, -0.5, 1.5), "world", 0.25);
  EXPECT_EQ(m.name, "pin_4");
  EXPECT_EQ(m.header.frame_id, "world");
  EXPECT_EQ(m.pose.position.x, 0.5);
  EXPECT_EQ(m.pose.position.y, -0.5);
  EXPECT_EQ(m.pose.position.z, 1.5);
  EXPECT_EQ(m.pose.orientation.w, 1.0);
  EXPECT_FLOAT_EQ(m.scale, 0.25f);

  int free = 0, planes = 0;
  std::vector<Vec3> axes;
  for (const auto& c : m.controls) {
    EXPECT_FALSE(c.markers.empty()) << c.name << " has nothing to grab";
    EXPECT_EQ(c.orientation_mode, InteractiveMarkerControl::FIXED) << c.name;
    switch (c.interaction_mode) {
      case InteractiveMarkerControl::MOVE_3D: ++free; break;
      case InteractiveMarkerControl::MOVE_AXIS: axes.push_back(axisOf(c)); break;
      case InteractiveMarkerControl::MOVE_PLANE:
        ++planes;
        EXPECT_TRUE(axisOf(c).isApprox(Vec3::UnitZ(), 1e-9)) << "plane normal " << axisOf(c);
        break;
      default: ADD_FAILURE() << "unexpected control " << c.name;
    }
  }
  EXPECT_EQ(free, 1);
  EXPECT_EQ(planes, 1);
  ASSERT_EQ(axes.size(), 3u);
  EXPECT_TRUE(axes[0].isApprox(Vec3::UnitX(), 1e-9)) << axes[0];
  EXPECT_TRUE(axes[1].isApprox(Vec3::UnitY(), 1e-9)) << axes[1];
  EXPECT_TRUE(axes[2].isApprox(Vec3::UnitZ(), 1e-9)) << axes[2];
}

TEST(PinHandles, ScaleWithTheCloth) {
  // 0.2 m handles once buried a 1 m cloth.
  EXPECT_DOUBLE_EQ(handleSizeFor(1.0), 0.1);
  EXPECT_DOUBLE_EQ(handleSizeFor(2.4), 0.24);
  EXPECT_DOUBLE_EQ(handleSizeFor(0.05), 0.02);  // still grabbable
  EXPECT_DOUBLE_EQ(handleSizeFor(100.0), 0.5);
  EXPECT_EQ(makePinHandle(3, Vec3(0, 0, 1), "world", handleSizeFor(1.0)).scale, 0.1f);
}

}  // namespace
}  // namespace cloth_sim::node
