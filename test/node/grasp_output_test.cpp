// Grasp messages and markers, and the point cloud: pure conversions, no master.
#include <cmath>

#include <gtest/gtest.h>
#include <sensor_msgs/point_cloud2_iterator.h>

#include "cloth_sim/node/grasp_output.h"
#include "cloth_sim/node/point_cloud.h"

namespace cloth_sim::node {
namespace {

Grasp turnedGrasp() {
  Grasp g;
  g.id = 4;
  g.vertices = {1, 2};
  g.pose = Pose(Eigen::Translation3d(1, 2, 3) * Eigen::AngleAxisd(M_PI / 2, Vec3::UnitZ()));
  g.wrench.force = Vec3(0, -2, -9.81);    // in the simulation frame
  g.wrench.torque = Vec3(1, 0, 0);
  return g;
}

TEST(GraspOutput, WrenchIsRotatedIntoTheGraspFrame) {
  const geometry_msgs::Wrench w = wrenchInGraspFrame(turnedGrasp(), Vec3::Zero());
  // The frame is turned +90 deg about z, so world -y is the frame's -x: R^T (0, -2, z) = (-2, 0, z).
  EXPECT_NEAR(w.force.x, -2.0, 1e-12);
  EXPECT_NEAR(w.force.y, 0.0, 1e-12);
  EXPECT_NEAR(w.force.z, -9.81, 1e-12);
  EXPECT_NEAR(w.torque.x, 0.0, 1e-12);
  EXPECT_NEAR(w.torque.y, -1.0, 1e-12);
}

TEST(GraspOutput, TorqueIsAboutTheTfFrameOriginNotTheOffsetPoint) {
  // Held 0.1 m along the frame's x from its origin, a pure downward pull F about the grasp
  // point is a torque offset x F about the frame's origin: (0.1, 0, 0) x (0, 0, -9.81).
  Grasp g;
  g.wrench.force = Vec3(0, 0, -9.81);
  const geometry_msgs::Wrench w = wrenchInGraspFrame(g, Vec3(0.1, 0, 0));
  EXPECT_NEAR(w.torque.x, 0.0, 1e-12);
  EXPECT_NEAR(w.torque.y, 0.981, 1e-12);
  EXPECT_NEAR(w.torque.z, 0.0, 1e-12);
}

TEST(GraspOutput, InfoCarriesFrameOffsetVerticesPoseLagAndStaleness) {
  GraspFrames::Tracked tracked{"gripper", Vec3(0, 0, 0.1), Pose::Identity(), true};
  Grasp g = turnedGrasp();
  g.lag = 0.25;  // the frame moved faster than the pins' speed limit
  const GraspInfo info = toGraspInfo(g, tracked);
  EXPECT_DOUBLE_EQ(info.lag, 0.25);
  EXPECT_EQ(info.id, 4);
  EXPECT_EQ(info.frame_id, "gripper");
  EXPECT_DOUBLE_EQ(info.offset.z, 0.1);
  EXPECT_EQ(info.vertices, (std::vector<int>{1, 2}));
  EXPECT_DOUBLE_EQ(info.pose.position.y, 2.0);
  EXPECT_NEAR(info.pose.orientation.z, std::sin(M_PI / 4), 1e-12);
  EXPECT_TRUE(info.frame_stale);
}

TEST(GraspOutput, ArrowFromTheOriginAlongTheForceAndDeleteWhenReleased) {
  std_msgs::Header header;
  header.frame_id = "world";
  const visualization_msgs::Marker arrow = graspArrow(turnedGrasp(), false, 0.1, header);
  EXPECT_EQ(arrow.ns, names::kGraspsNs);
  EXPECT_EQ(arrow.type, visualization_msgs::Marker::ARROW);
  ASSERT_EQ(arrow.points.size(), 2u);
  EXPECT_DOUBLE_EQ(arrow.points[0].z, 3.0);
  EXPECT_NEAR(arrow.points[1].z, 3.0 - 0.981, 1e-12);

  tf2::BufferCore buffer;
  GraspFrames frames(buffer, "world", 0.5);
  std::set<int> shown;
  visualization_msgs::MarkerArray out;
  appendGraspMarkers({turnedGrasp()}, frames, 0.1, header, shown, out);
  EXPECT_EQ(shown, std::set<int>{4});
  out.markers.clear();
  appendGraspMarkers({}, frames, 0.1, header, shown, out);
  ASSERT_EQ(out.markers.size(), 1u);
  EXPECT_EQ(out.markers[0].action, visualization_msgs::Marker::DELETE);
  EXPECT_EQ(out.markers[0].id, 4);
  EXPECT_TRUE(shown.empty());
}

TEST(PointCloud, PointsAndUnitNormalsPerParticle) {
  // Two triangles of a unit square in the xy plane, and one lone particle.
  Points x(3, 5);
  x << 0, 1, 1, 0, 5,  //
      0, 0, 1, 1, 5,   //
      0, 0, 0, 0, 5;
  Eigen::Matrix3Xi tri(3, 2);
  tri << 0, 0,  //
      1, 2,     //
      2, 3;
  std_msgs::Header header;
  header.frame_id = "world";
  header.stamp = ros::Time(12.5);
  const sensor_msgs::PointCloud2 cloud = toPointCloud(x, tri, header);
  EXPECT_EQ(cloud.width, 5u);
  EXPECT_EQ(cloud.height, 1u);
  EXPECT_EQ(cloud.header.stamp, ros::Time(12.5));
  ASSERT_EQ(cloud.fields.size(), 6u);
  EXPECT_EQ(cloud.fields[3].name, "normal_x");
  sensor_msgs::PointCloud2ConstIterator<float> p(cloud, "x"), n(cloud, "normal_x");
  for (int i = 0; i < 5; ++i, ++p, ++n) {
    EXPECT_FLOAT_EQ(p[0], static_cast<float>(x(0, i)));
    EXPECT_FLOAT_EQ(p[2], static_cast<float>(x(2, i)));
    EXPECT_FLOAT_EQ(n[2], i < 4 ? 1.0f : 0.0f) << i;  // +z for the square, none for the lone one
  }
}

}  // namespace
}  // namespace cloth_sim::node
