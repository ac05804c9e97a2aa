// GraspSet: a grasp holds its particles as hard pins where they are, refuses bad grasps leaving
// the pins untouched, moves its targets with its frame (at most a given move a placement,
// rigidly, behind a frame that jumps), sums its pins' loads into a wrench and
// lets go. Pure: pins and positions, no solver.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "cloth_sim/core/simulation/grasp_set.h"

namespace cloth_sim {
namespace {

constexpr double kNoLimit = std::numeric_limits<double>::infinity();  ///< m: placed on the frame at once

/// Four particles at the corners of a unit square at z = 1.
Points square() {
  Points x(3, 4);
  x << 0, 1, 0, 1, 0, 0, 1, 1, 1, 1, 1, 1;
  return x;
}

TEST(GraspSet, HoldsEachParticleAsAHardPinWhereItIs) {
  const Points x = square();
  PinSet pins;
  GraspSet grasps;
  const Pose pose = Eigen::Translation3d(0.5, 0.5, 2.0) * Pose::Identity();
  const int id = grasps.add({1, 3}, pose, x, pins);
  ASSERT_EQ(pins.size(), 2u);
  const Grasp* g = grasps.find(id);
  ASSERT_NE(g, nullptr);
  for (std::size_t k = 0; k < 2; ++k) {
    const Pin* pin = pins.find(g->pin_ids[k]);
    ASSERT_NE(pin, nullptr);
    EXPECT_TRUE(pin->isHard());
    EXPECT_EQ(pin->vertex, g->vertices[k]);
    EXPECT_EQ(pin->target, Vec3(x.col(g->vertices[k])));
    EXPECT_EQ(grasps.graspOf(pin->id), g);
    EXPECT_NEAR((pose * Vec3(g->local.col(static_cast<Eigen::Index>(k))) - pin->target).norm(), 0.0,
                1e-15);
  }
  EXPECT_EQ(grasps.find(id + 1), nullptr);
}

TEST(GraspSet, BadGraspsAreRefusedLeavingThePinsUntouched) {
  const Points x = square();
  PinSet pins;
  pins.add(0, x.col(0), 0.0, 4);
  GraspSet grasps;
  auto refused = [&](const std::vector<int>& vertices, const Pose& pose, const std::string& why) {
    try {
      grasps.add(vertices, pose, x, pins);
      ADD_FAILURE() << "accepted: " << why;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(why), std::string::npos) << e.what();
    }
    EXPECT_EQ(pins.size(), 1u);
    EXPECT_TRUE(grasps.empty());
  };
  refused({}, Pose::Identity(), "no particle to hold");
  refused({4}, Pose::Identity(), "vertex 4 is out of range [0, 4)");
  refused({1, 1}, Pose::Identity(), "vertex 1 is listed twice");
  refused({1, 0}, Pose::Identity(), "vertex 0 is already pinned (pin 0)");
  Pose bad = Pose::Identity();
  bad.translation().x() = std::nan("");
  refused({1}, bad, "pose is not finite");
}

TEST(GraspSet, PlaceMovesTheTargetsWithTheFrameAndKeepsItOnABadAnswer) {
  const Points x = square();
  PinSet pins;
  GraspSet grasps;
  grasps.add({2, 3}, Pose::Identity(), x, pins);
  const Pose turned =
      Eigen::Translation3d(0.0, 0.0, 0.5) * Eigen::AngleAxisd(M_PI / 2, Vec3::UnitZ());
  bool answer_nan = false;
  grasps.setPoseSource([&](int, double) {
    if (!answer_nan) return turned;
    Pose p = turned;
    p.translation().z() = std::nan("");
    return p;
  });
  PinSet copy = pins;
  grasps.place(0.1, kNoLimit, pins, &copy);
  const Grasp& g = grasps.grasps()[0];
  for (std::size_t k = 0; k < 2; ++k) {
    const Vec3 expected = turned * Vec3(x.col(g.vertices[k]));
    EXPECT_NEAR((pins.find(g.pin_ids[k])->target - expected).norm(), 0.0, 1e-15);
    EXPECT_EQ(copy.find(g.pin_ids[k])->target, pins.find(g.pin_ids[k])->target);
  }
  answer_nan = true;
  const Vec3 before = pins.find(g.pin_ids[0])->target;
  grasps.place(0.2, kNoLimit, pins, nullptr);
  EXPECT_EQ(pins.find(g.pin_ids[0])->target, before);
  EXPECT_TRUE(g.pose.matrix().allFinite());
}

TEST(GraspSet, AGripperSetDownOnAStackStopsOnIt) {
  const Points x = square();
  PinSet pins;
  GraspSet grasps;
  grasps.add({0, 1}, Pose::Identity(), x, pins);
  // The frame goes down 0.4 m and sideways 0.3 m; the cloth below pushes particle 1 up: the
  // gripper stops where it is (sliding along the push, it went down the stack's slope).
  const Pose down = Eigen::Translation3d(0.3, 0.0, -0.4) * Pose::Identity();
  grasps.setPoseSource([&](int, double) { return down; });
  Points push = Points::Zero(3, 4);
  push.col(1) = Vec3(0.0, 0.0, 2.0);  // N
  grasps.place(0.1, kNoLimit, pins, nullptr, push);
  const Grasp& g = grasps.grasps()[0];
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_EQ(pins.find(g.pin_ids[k])->target, Vec3(x.col(g.vertices[k]))) << "stopped";
  }
  EXPECT_NEAR(g.lag, 0.5, 1e-12);  // how far it stays behind its frame
  EXPECT_TRUE(g.stopped);
  // Pushed the way it goes, or not at all, it follows its frame.
  push.col(1) = Vec3(0.0, 0.0, -2.0);
  grasps.place(0.2, kNoLimit, pins, nullptr, push);
  EXPECT_NEAR(pins.find(g.pin_ids[0])->target.z(), 0.6, 1e-15);
  EXPECT_NEAR(g.lag, 0.0, 1e-15);
  EXPECT_FALSE(g.stopped);
}

/// The largest distance between the targets of @p pins_ids in @p a and in @p b.
double farthest(const PinSet& a, const PinSet& b, const std::vector<int>& pin_ids) {
  double d = 0.0;
  for (int id : pin_ids) d = std::max(d, (a.find(id)->target - b.find(id)->target).norm());
  return d;
}

TEST(GraspSet, AFrameThatJumpsIsFollowedRigidlyAtMostTheGivenMoveAPlacement) {
  // Issue 23: a gripper frame yanked 1 m knots the cloth. The held particles go there at most
  // max_move a placement, keeping the grasp's shape, and the lag says how far behind they are.
  const Points x = square();
  PinSet pins;
  GraspSet grasps;
  grasps.add({0, 1, 3}, Pose::Identity(), x, pins);
  const Grasp& g = grasps.grasps()[0];
  const Pose down(Eigen::Translation3d(0.0, 0.0, -1.0));
  grasps.setPoseSource([&](int, double) { return down; });
  PinSet before = pins;
  grasps.place(0.1, 0.05, pins, nullptr);
  EXPECT_NEAR(farthest(before, pins, g.pin_ids), 0.05, 1e-15);
  EXPECT_NEAR(g.lag, 0.95, 1e-15);
  EXPECT_EQ(g.frame.matrix(), down.matrix());
  for (int k = 0; k < 18; ++k) grasps.place(0.2, 0.05, pins, nullptr);
  EXPECT_NEAR(g.lag, 0.05, 1e-12);
  grasps.place(0.3, 0.05, pins, nullptr);  // caught up: held on the frame, exactly
  EXPECT_EQ(g.lag, 0.0);
  EXPECT_EQ(g.pose.matrix(), down.matrix());
  // A half turn about z and 1 m up: every placement moves no particle more than 0.05 m, the
  // distances between the held particles are kept, and the frame is reached.
  const Pose turned =
      Eigen::Translation3d(0.0, 0.0, 1.0) * Eigen::AngleAxisd(M_PI * 0.99, Vec3::UnitZ());
  grasps.setPoseSource([&](int, double) { return turned; });
  double last_lag = std::numeric_limits<double>::infinity();
  int placements = 0;
  for (; placements < 200 && (placements == 0 || g.lag > 0.0); ++placements) {
    before = pins;
    grasps.place(1.0, 0.05, pins, nullptr);
    EXPECT_LE(farthest(before, pins, g.pin_ids), 0.05 + 1e-12) << "placement " << placements;
    const Vec3 a = pins.find(g.pin_ids[0])->target, b = pins.find(g.pin_ids[1])->target,
               c = pins.find(g.pin_ids[2])->target;
    EXPECT_NEAR((a - b).norm(), 1.0, 1e-12);
    EXPECT_NEAR((b - c).norm(), 1.0, 1e-12);
    EXPECT_NEAR((a - c).norm(), std::sqrt(2.0), 1e-12);
    EXPECT_LT(g.lag, last_lag);
    last_lag = g.lag;
  }
  EXPECT_EQ(g.lag, 0.0) << "after " << placements << " placements";
  EXPECT_GT(placements, 50);  // 2 m up (from 1 m below) and a corner swung about 1.5 m
  EXPECT_EQ(g.pose.matrix(), turned.matrix());
}

TEST(GraspSet, WrenchIsItsPinsLoadsAndTheirTorqueAboutTheFrame) {
  const Points x = square();
  PinSet pins;
  pins.add(0, x.col(0), 0.0, 4);  // the user's own: not the grasp's
  GraspSet grasps;
  const Pose pose = Eigen::Translation3d(0.5, 0.5, 1.0) * Pose::Identity();
  grasps.add({1, 2}, pose, x, pins);
  const std::vector<Vec3> loads = {Vec3(9, 9, 9), Vec3(0, 0, -1), Vec3(0, 0, -2)};
  grasps.updateWrenches(pins, loads, x);
  const Wrench& w = grasps.grasps()[0].wrench;
  EXPECT_EQ(w.force, Vec3(0, 0, -3));
  const Vec3 o = pose.translation();
  const Vec3 torque = (Vec3(x.col(1)) - o).cross(loads[1]) + (Vec3(x.col(2)) - o).cross(loads[2]);
  EXPECT_NEAR((w.torque - torque).norm(), 0.0, 1e-15);
}

TEST(GraspSet, RemoveLetsGoOfItsPinsOnly) {
  const Points x = square();
  PinSet pins;
  const int own = pins.add(0, x.col(0), 0.0, 4);
  GraspSet grasps;
  const int id = grasps.add({1, 2}, Pose::Identity(), x, pins);
  const int held = grasps.grasps()[0].pin_ids[0];
  EXPECT_NO_THROW(grasps.requireNotGrasped(own, "moved"));
  try {
    grasps.requireNotGrasped(held, "moved");
    ADD_FAILURE() << "a grasp's pin may be moved on its own";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("belongs to grasp"), std::string::npos) << e.what();
  }
  grasps.remove(id, pins);
  EXPECT_EQ(pins.size(), 1u);
  EXPECT_NE(pins.find(own), nullptr);
  EXPECT_EQ(grasps.graspOf(held), nullptr);
  EXPECT_THROW(grasps.remove(id, pins), std::invalid_argument);
  // Ids keep counting up: a new grasp is never mistaken for the released one.
  EXPECT_GT(grasps.add({3}, Pose::Identity(), x, pins), id);
}

}  // namespace
}  // namespace cloth_sim
