// The robot's links as colliders (urdfColliders): shapes, origins and refusals, no master.
#include <cmath>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "cloth_sim/node/urdf_colliders.h"
#include "error_of.h"

namespace cloth_sim::node {
namespace {

std::string file(const std::string& path) {
  std::ifstream in(std::string(CLOTH_SIM_SOURCE_DIR) + "/" + path);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

std::string robot(const std::string& link_body) {
  return "<robot name='r'><link name='base'/><link name='tool'>" + link_body +
         "</link><joint name='j' type='fixed'><parent link='base'/><child link='tool'/></joint></robot>";
}

MeshPathResolver asIs() {
  return [](const std::string& url) { return url; };
}

TEST(UrdfColliders, TheGrippersFingersAreBoxesOnTheirFrames) {
  const std::vector<BodyCollider> bodies = urdfColliders(
      file("config/robots/parallel_gripper.urdf"), {"finger_upper", "finger_lower"}, 0.004, 0.8, asIs());
  ASSERT_EQ(bodies.size(), 2u);
  EXPECT_EQ(bodies[0].name, "finger_upper");
  EXPECT_TRUE(bodies[0].follows_frame);
  EXPECT_EQ(bodies[0].geometry.shape, BodyShape::kBox);
  EXPECT_TRUE(bodies[0].geometry.size.isApprox(Vec3(0.04, 0.16, 0.02)));
  EXPECT_DOUBLE_EQ(bodies[0].origin.translation().z(), 0.01);
  EXPECT_DOUBLE_EQ(bodies[1].origin.translation().z(), -0.01);
  EXPECT_DOUBLE_EQ(bodies[1].margin, 0.004);
  EXPECT_DOUBLE_EQ(bodies[1].friction, 0.8);
}

TEST(UrdfColliders, SpheresCylindersAndTurnedOrigins) {
  const std::vector<BodyCollider> bodies = urdfColliders(
      robot("<collision><geometry><sphere radius='0.03'/></geometry></collision>"
            "<collision><origin xyz='0 0 0.1' rpy='1.5707963267948966 0 0'/>"
            "<geometry><cylinder radius='0.02' length='0.1'/></geometry></collision>"),
      {"tool"}, 0.005, 0.0, asIs());
  ASSERT_EQ(bodies.size(), 2u);
  EXPECT_EQ(bodies[0].geometry.shape, BodyShape::kSphere);
  EXPECT_DOUBLE_EQ(bodies[0].geometry.radius, 0.03);
  EXPECT_EQ(bodies[1].geometry.shape, BodyShape::kCapsule);
  EXPECT_DOUBLE_EQ(bodies[1].geometry.length, 0.1);
  // rolled a quarter turn about x: the cylinder's axis (its z) along -y
  EXPECT_TRUE((bodies[1].origin.linear() * Vec3::UnitZ()).isApprox(-Vec3::UnitY(), 1e-12));
}

TEST(UrdfColliders, RefusesWhatItCannotUse) {
  const std::string gripper = file("config/robots/parallel_gripper.urdf");
  EXPECT_EQ(test::errorOf([&] { urdfColliders("", {"x"}, 0.005, 0, asIs()); }),
            "the robot description is empty");
  EXPECT_EQ(test::errorOf([&] { urdfColliders("<robot", {"x"}, 0.005, 0, asIs()); }),
            "the robot description is not a URDF that parses");
  EXPECT_EQ(test::errorOf([&] { urdfColliders(gripper, {"wrist"}, 0.005, 0, asIs()); }),
            "link 'wrist' is not in the robot description");
  EXPECT_EQ(test::errorOf([&] { urdfColliders(gripper, {"gripper_palm"}, 0.005, 0, asIs()); }),
            "link 'gripper_palm' has no <collision> geometry");
  EXPECT_NE(test::errorOf([&] {
              urdfColliders(robot("<collision><geometry><sphere radius='0'/></geometry></collision>"),
                            {"tool"}, 0.005, 0, asIs());
            }).find("link 'tool' collision 0: sphere collider radius 0 must be in (0, 1e+06] m"),
            std::string::npos);
  EXPECT_NE(test::errorOf([&] {
              urdfColliders(robot("<collision><geometry><mesh filename='/no/such.stl'/></geometry>"
                                  "</collision>"),
                            {"tool"}, 0.005, 0, asIs());
            }).find("link 'tool' collision 0: /no/such.stl: cannot open"),
            std::string::npos);
  EXPECT_EQ(resolveMeshUrl("file:///a/b.stl"), "/a/b.stl");
  EXPECT_EQ(resolveMeshUrl("/a/b.stl"), "/a/b.stl");
}

}  // namespace
}  // namespace cloth_sim::node
