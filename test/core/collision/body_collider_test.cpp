// Rigid bodies (body_collider.h): the shapes' distances, the set's refusals and motion, and the
// contact of one particle over a step: continuous, on the entry side, with friction and squeeze.
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "cloth_sim/core/collision/body_collider.h"

namespace cloth_sim {
namespace {

using Iso = Eigen::Isometry3d;

BodyCollider box(const Vec3& size, const Iso& pose = Iso::Identity(), double margin = 0.005,
                 double friction = 0.0) {
  BodyCollider b;
  b.geometry.shape = BodyShape::kBox;
  b.geometry.size = size;
  b.frame_pose = b.previous_frame_pose = pose;
  b.margin = margin;
  b.friction = friction;
  return b;
}

Iso at(double x, double y, double z) { return Iso(Eigen::Translation3d(x, y, z)); }

std::string refusal(const BodyCollider& b) {
  try {
    BodySet().add(b);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(BodyGeometry, DistancesAreExact) {
  BodyGeometry g;
  g.shape = BodyShape::kBox;
  g.size = Vec3(2, 4, 6);
  EXPECT_DOUBLE_EQ(g.distance(Vec3(3, 0, 0)), 2.0);                  // face
  EXPECT_DOUBLE_EQ(g.distance(Vec3(4, 5, 0)), std::hypot(3.0, 3.0));  // edge
  EXPECT_DOUBLE_EQ(g.distance(Vec3(0.5, 0, 0)), -0.5);               // inside: nearest face
  EXPECT_TRUE(g.gradient(Vec3(0.5, 0, 0)).isApprox(Vec3::UnitX()));
  EXPECT_TRUE(g.gradient(Vec3(0, 0, -2.9)).isApprox(-Vec3::UnitZ()));
  g.shape = BodyShape::kCapsule;
  g.radius = 0.1;
  g.length = 1.0;
  EXPECT_DOUBLE_EQ(g.distance(Vec3(0.3, 0, 0.4)), 0.2);   // beside the segment
  EXPECT_DOUBLE_EQ(g.distance(Vec3(0, 0, 0.9)), 0.3);     // beyond a cap
  EXPECT_DOUBLE_EQ(g.boundingRadius(), 0.6);
  g.shape = BodyShape::kSphere;
  EXPECT_DOUBLE_EQ(g.distance(Vec3(0, 0.5, 0)), 0.4);
}

TEST(BodySet, RefusesBadBodiesNamingTheField) {
  EXPECT_NE(refusal(box(Vec3(0, 1, 1))).find("box collider size 0 must be in (0, 1e+06] m"),
            std::string::npos);
  EXPECT_NE(refusal(box(Vec3(1, 1, 1), at(0, 0, 0), 0.0)).find("box collider margin 0"),
            std::string::npos);
  EXPECT_NE(refusal(box(Vec3(1, 1, 1), at(0, 0, 0), 0.01, -1)).find("box collider friction -1"),
            std::string::npos);
  EXPECT_NE(refusal(box(Vec3(1, 1, 1), at(NAN, 0, 0))).find("pose must be finite"),
            std::string::npos);
  BodyCollider capsule;
  capsule.geometry.shape = BodyShape::kCapsule;
  capsule.geometry.radius = 0.1;
  capsule.geometry.length = -1;
  EXPECT_NE(refusal(capsule).find("capsule collider length -1"), std::string::npos);
  BodyCollider mesh;
  mesh.geometry.shape = BodyShape::kMesh;
  EXPECT_NE(refusal(mesh).find("the mesh has no triangle"), std::string::npos);
  EXPECT_THROW(bodyShapeFromName("cone"), std::invalid_argument);
  EXPECT_EQ(bodyShapeFromName("capsule"), BodyShape::kCapsule);
  BodySet set;
  EXPECT_THROW(set.remove(3), std::invalid_argument);
  EXPECT_THROW(set.setFramePose(0, at(0, 0, 0)), std::invalid_argument);
}

TEST(BodySet, PlaceFollowsTheSourceAndKeepsTheStart) {
  BodySet set;
  BodyCollider moving = box(Vec3(1, 1, 1));
  moving.follows_frame = true;
  const int still = set.add(box(Vec3(1, 1, 1), at(5, 0, 0)));
  const int id = set.add(moving);
  EXPECT_FALSE(set.find(id)->placed);  // nowhere until its frame is seen
  set.place(0.5, [](int, double t) { return at(t, 0, 0); });
  EXPECT_TRUE(set.find(id)->placed);  // appears there, sweeping nothing
  EXPECT_DOUBLE_EQ(set.find(id)->previous_frame_pose.translation().x(), 0.5);
  set.place(0.75, [](int, double t) { return at(t, 0, 0); });
  EXPECT_DOUBLE_EQ(set.find(id)->frame_pose.translation().x(), 0.75);
  EXPECT_DOUBLE_EQ(set.find(id)->previous_frame_pose.translation().x(), 0.5);
  EXPECT_DOUBLE_EQ(set.find(still)->frame_pose.translation().x(), 5.0);  // not on a frame
  set.place(1.0, [](int, double) { return at(NAN, 0, 0); });            // kept
  EXPECT_DOUBLE_EQ(set.find(id)->frame_pose.translation().x(), 0.75);
  EXPECT_DOUBLE_EQ(set.find(id)->previous_frame_pose.translation().x(), 0.75);
  set.remove(still);
  EXPECT_EQ(set.bodies().size(), 1u);
}

TEST(BodyContact, AParticleCannotPassAStillBoxAtAnySpeed) {
  const BodyCollider b = box(Vec3(0.02, 1, 1));  // a 2 cm plate
  for (double speed : {0.01, 1.0, 100.0, 1e4}) {
    Vec3 end(speed, 0.1, 0.2);
    ASSERT_TRUE(collideWithBodies({b}, Vec3(-0.05, 0.1, 0.2), end, std::nullopt)) << speed;
    EXPECT_NEAR(end.x(), -0.015, 1e-12) << speed;  // on the entry side, at the margin
    EXPECT_DOUBLE_EQ(end.y(), 0.1);
  }
}

TEST(BodyContact, AFastThinPlateSweepsAStillParticleAhead) {
  // A 1 cm plate moving 1 m in one step through a particle at rest pushes it ahead.
  BodyCollider b = box(Vec3(0.01, 1, 1), at(0.5, 0, 0));
  b.previous_frame_pose = at(-0.5, 0, 0);
  Vec3 end(0, 0, 0);
  ASSERT_TRUE(collideWithBodies({b}, Vec3(0, 0, 0), end, std::nullopt));
  EXPECT_NEAR(end.x(), 0.5 + 0.005 + 0.005, 1e-9);
  // A turning paddle (a quarter turn about z in one step) sweeps a particle in its way too.
  BodyCollider paddle = box(Vec3(1, 0.01, 0.2));
  paddle.previous_frame_pose = Iso(Eigen::AngleAxisd(-M_PI / 4, Vec3::UnitZ()));
  paddle.frame_pose = Iso(Eigen::AngleAxisd(M_PI / 4, Vec3::UnitZ()));
  Vec3 p(0.3, 0, 0);
  ASSERT_TRUE(collideWithBodies({paddle}, Vec3(0.3, 0, 0), p, std::nullopt));
  EXPECT_GT(std::atan2(p.y(), p.x()), M_PI / 4);  // ahead of the paddle
}

TEST(BodyContact, FrictionHoldsWhatItsLoadCanAndNoMore) {
  // A particle sliding 1 mm per step over a box top, pressed by its weight (h^2 g = 0.1 mm per
  // step into the surface): mu = 20 holds it (2 mm > 1 mm), mu = 5 cuts 0.5 mm of the slide.
  const Vec3 start(0, 0, 0.5 + 0.005);
  const Vec3 free(0.001, 0, -1e-4);
  for (double mu : {0.0, 5.0, 20.0}) {
    const BodyCollider b = box(Vec3(1, 1, 1), Iso::Identity(), 0.005, mu);
    Vec3 end = start + free;
    collideWithBodies({b}, start, end, free);
    EXPECT_NEAR(end.z(), start.z(), 1e-12);
    EXPECT_NEAR(end.x(), std::max(0.0, 0.001 - mu * 1e-4), 1e-12) << mu;
  }
}

TEST(BodyContact, ASqueezedParticleIsCentredAndCarriedByFriction) {
  // Two fingers 1 cm apart with 1 cm margins overlap by 1 cm; both lift 2 mm this step.
  BodyCollider upper = box(Vec3(0.1, 0.1, 0.02), at(0, 0, 0.015), 0.01, 1.0);
  BodyCollider lower = box(Vec3(0.1, 0.1, 0.02), at(0, 0, -0.015), 0.01, 1.0);
  upper.previous_frame_pose = at(0, 0.002, 0.015);  // moving along -y
  lower.previous_frame_pose = at(0, 0.002, -0.015);
  const Vec3 start(0.01, 0.002, 0.001);
  Vec3 end = start;  // the solve left it where it was
  ASSERT_TRUE(collideWithBodies({upper, lower}, start, end, std::nullopt));
  EXPECT_NEAR(end.z(), 0.0, 1e-6);  // centred: 5 mm into each margin
  EXPECT_NEAR(end.y(), 0.0, 1e-9);  // carried with the fingers
  upper.friction = lower.friction = 0.0;
  end = start;
  collideWithBodies({upper, lower}, start, end, std::nullopt);
  EXPECT_NEAR(end.y(), 0.002, 1e-9);  // without friction the fingers slide past it
}

TEST(BodyContact, AMeshBodyOnAMovingFrameBlocks) {
  TriangleMesh quad;
  quad.vertices.resize(3, 4);
  quad.vertices << -1, 1, 1, -1, -1, -1, 1, 1, 0, 0, 0, 0;
  quad.triangles.resize(3, 2);
  quad.triangles << 0, 0, 1, 2, 2, 3;
  BodyCollider b;
  b.geometry.shape = BodyShape::kMesh;
  b.geometry.mesh = std::make_shared<MeshObstacle>(quad, 0.01, 0.0);
  b.frame_pose = at(0, 0, 1.0);  // the plane rose from z = 0 to 1 this step
  b.previous_frame_pose = at(0, 0, 0.0);
  Vec3 end(0.2, 0.1, 0.5);  // a particle that stayed above the old plane
  ASSERT_TRUE(collideWithBodies({b}, Vec3(0.2, 0.1, 0.5), end, std::nullopt));
  EXPECT_NEAR(end.z(), 1.01, 1e-9);  // lifted above the plane, not left below it
  BodySet set;
  b.margin = 0.5;  // ignored: a mesh keeps its own thickness
  EXPECT_DOUBLE_EQ(set.find(set.add(b))->margin, 0.01);
}

}  // namespace
}  // namespace cloth_sim
