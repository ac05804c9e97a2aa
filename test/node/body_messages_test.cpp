// Rigid-body colliders <-> messages (body_messages.h): requests, info and markers, no master.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "cloth_sim/node/body_messages.h"
#include "cloth_sim/node/names.h"
#include "error_of.h"

namespace cloth_sim::node {
namespace {

MeshPathResolver asIs() {
  return [](const std::string& url) { return url; };
}

AddCollider::Request boxRequest() {
  AddCollider::Request r;
  r.shape = "box";
  r.size.x = 0.1;
  r.size.y = 0.2;
  r.size.z = 0.3;
  r.origin.position.z = 0.05;
  r.friction = 0.7;
  return r;
}

TEST(BodyMessages, ARequestBecomesABodyWithDefaults) {
  const BodyCollider b = bodyFromRequest(boxRequest(), asIs());
  EXPECT_EQ(b.geometry.shape, BodyShape::kBox);
  EXPECT_TRUE(b.geometry.size.isApprox(Vec3(0.1, 0.2, 0.3)));
  EXPECT_DOUBLE_EQ(b.margin, 0.005);  // 0 asks for the default
  EXPECT_DOUBLE_EQ(b.friction, 0.7);
  EXPECT_TRUE(b.origin.linear().isIdentity());  // a zero quaternion is the identity
  EXPECT_DOUBLE_EQ(b.origin.translation().z(), 0.05);
}

TEST(BodyMessages, BadRequestsAreRefusedNamingTheField) {
  AddCollider::Request r = boxRequest();
  r.shape = "cone";
  EXPECT_EQ(test::errorOf([&] { bodyFromRequest(r, asIs()); }),
            "shape 'cone' must be one of sphere, capsule, box, mesh");
  r = boxRequest();
  r.size.y = -1;
  EXPECT_NE(test::errorOf([&] { bodyFromRequest(r, asIs()); }).find("box collider size -1"),
            std::string::npos);
  r = boxRequest();
  r.margin = 5;
  EXPECT_EQ(test::errorOf([&] { bodyFromRequest(r, asIs()); }), "margin 5 must be in (0, 1] m");
  r = boxRequest();
  r.origin.orientation.w = 2;
  EXPECT_NE(test::errorOf([&] { bodyFromRequest(r, asIs()); }).find("unit quaternion"),
            std::string::npos);
  r = boxRequest();
  r.origin.position.x = NAN;
  EXPECT_NE(test::errorOf([&] { bodyFromRequest(r, asIs()); }).find("origin.position"),
            std::string::npos);
  r = boxRequest();
  r.shape = "mesh";
  EXPECT_EQ(test::errorOf([&] { bodyFromRequest(r, asIs()); }),
            "mesh_file is empty: name an OBJ or STL file");
}

TEST(BodyMessages, MarkersDrawPlacedBodiesAndDeleteGoneOnes) {
  BodyCollider box = bodyFromRequest(boxRequest(), asIs());
  box.id = 3;
  box.frame_pose = Eigen::Isometry3d(Eigen::Translation3d(1, 0, 0));
  BodyCollider capsule = box;
  capsule.id = 4;
  capsule.geometry.shape = BodyShape::kCapsule;
  capsule.geometry.radius = 0.02;
  capsule.geometry.length = 0.1;
  BodyCollider hidden = box;
  hidden.id = 5;
  hidden.placed = false;
  std::set<int> shown{9};
  visualization_msgs::MarkerArray out;
  std_msgs::Header header;
  header.frame_id = "world";
  appendBodyMarkers({box, capsule, hidden}, header, shown, out);
  ASSERT_EQ(out.markers.size(), 5u);  // cube, cylinder + 2 caps, delete of 9
  EXPECT_EQ(out.markers[0].ns, names::kBodiesNs);
  EXPECT_EQ(out.markers[0].type, visualization_msgs::Marker::CUBE);
  EXPECT_DOUBLE_EQ(out.markers[0].pose.position.x, 1.0);
  EXPECT_DOUBLE_EQ(out.markers[0].pose.position.z, 0.05);
  EXPECT_DOUBLE_EQ(out.markers[2].pose.position.z, 0.05 + 0.05);  // the upper cap
  EXPECT_EQ(out.markers[4].action, visualization_msgs::Marker::DELETE);
  EXPECT_EQ(out.markers[4].id, 9);
  EXPECT_EQ(shown.count(5), 0u);
  const ColliderInfo info = toColliderInfo(hidden, "tool0", false);
  EXPECT_EQ(info.shape, "box");
  EXPECT_TRUE(info.frame_stale);  // not placed yet
}

}  // namespace
}  // namespace cloth_sim::node
