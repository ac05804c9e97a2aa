// Key-to-motion logic of pin_teleop, no terminal and no master.
#include <gtest/gtest.h>

#include "pin_teleop.h"

namespace cloth_sim::node {
namespace {

constexpr double kStep = 0.1;  // m

class PinTeleopTest : public ::testing::Test {
 protected:
  PinTeleopTest() : teleop_(kStep, 0.5) {
    teleop_.updatePins({{7, Vec3(0, 0, 1)}, {2, Vec3(1, 1, 1)}, {5, Vec3(-1, 0, 1)}}, 0.0);
  }
  PinTeleop teleop_;
};

TEST(PinTeleop, WithoutPinsNothingIsPublished) {
  PinTeleop t(kStep);
  EXPECT_EQ(t.selectedPin(), -1);
  const TeleopAction a = t.handleKey('i', 0.0);
  EXPECT_FALSE(a.publish);
  EXPECT_NE(a.status.find("waiting"), std::string::npos);
  EXPECT_FALSE(t.handleKey('n', 0.0).publish);
  EXPECT_FALSE(t.handleKey('k', 0.0).publish);
}

TEST_F(PinTeleopTest, SelectsTheLowestIdFirst) { EXPECT_EQ(teleop_.selectedPin(), 2); }

TEST_F(PinTeleopTest, EachMoveKeyMovesOneStepAlongItsAxis) {
  const std::pair<char, Vec3> keys[] = {
      {'i', Vec3(kStep, 0, 0)}, {',', Vec3(-kStep, 0, 0)}, {'j', Vec3(0, kStep, 0)},
      {'l', Vec3(0, -kStep, 0)}, {'t', Vec3(0, 0, kStep)}, {'b', Vec3(0, 0, -kStep)}};
  for (const auto& [key, delta] : keys) {
    PinTeleop t(kStep);
    t.updatePins({{2, Vec3(1, 1, 1)}}, 0.0);
    const TeleopAction a = t.handleKey(key, 1.0);
    EXPECT_TRUE(a.publish) << key;
    EXPECT_EQ(a.pin_id, 2) << key;
    EXPECT_TRUE(a.target.isApprox(Vec3(1, 1, 1) + delta, 1e-12)) << key << ": " << a.target;
    EXPECT_FALSE(a.quit);
  }
}

TEST_F(PinTeleopTest, PressesAccumulateBeforeTheStateCatchesUp) {
  teleop_.handleKey('i', 1.0);
  teleop_.updatePins({{7, Vec3(0, 0, 1)}, {2, Vec3(1, 1, 1)}, {5, Vec3(-1, 0, 1)}}, 1.1);  // stale
  const TeleopAction a = teleop_.handleKey('i', 1.2);
  EXPECT_TRUE(a.target.isApprox(Vec3(1.2, 1, 1), 1e-12)) << a.target;
}

TEST_F(PinTeleopTest, TheStateTargetIsAdoptedAfterTheHoldTime) {
  teleop_.handleKey('i', 1.0);
  teleop_.updatePins({{2, Vec3(3, 3, 3)}, {5, Vec3(-1, 0, 1)}, {7, Vec3(0, 0, 1)}}, 1.6);
  const TeleopAction a = teleop_.handleKey('t', 1.7);
  EXPECT_TRUE(a.target.isApprox(Vec3(3, 3, 3.1), 1e-12)) << a.target;
}

TEST_F(PinTeleopTest, NextAndPreviousCycleThroughIds) {
  EXPECT_FALSE(teleop_.handleKey('n', 0.0).publish);
  EXPECT_EQ(teleop_.selectedPin(), 5);
  teleop_.handleKey('n', 0.0);
  EXPECT_EQ(teleop_.selectedPin(), 7);
  teleop_.handleKey('n', 0.0);
  EXPECT_EQ(teleop_.selectedPin(), 2);  // wraps
  teleop_.handleKey('p', 0.0);
  EXPECT_EQ(teleop_.selectedPin(), 7);  // wraps back
  EXPECT_NE(teleop_.handleKey('p', 0.0).status.find("pin 5"), std::string::npos);
}

TEST_F(PinTeleopTest, HomeReturnsToWhereThePinWasFirstSeen) {
  teleop_.handleKey('i', 1.0);
  teleop_.handleKey('t', 1.0);
  const TeleopAction a = teleop_.handleKey('k', 1.0);
  EXPECT_TRUE(a.publish);
  EXPECT_TRUE(a.target.isApprox(Vec3(1, 1, 1), 1e-12)) << a.target;
}

TEST_F(PinTeleopTest, StepGrowsAndShrinksWithinBounds) {
  EXPECT_FALSE(teleop_.handleKey('q', 0.0).publish);
  EXPECT_NEAR(teleop_.step(), 0.125, 1e-12);
  teleop_.handleKey('z', 0.0);
  teleop_.handleKey('z', 0.0);
  EXPECT_NEAR(teleop_.step(), 0.08, 1e-12);
  for (int i = 0; i < 100; ++i) teleop_.handleKey('q', 0.0);
  EXPECT_EQ(teleop_.step(), 1.0);
  for (int i = 0; i < 100; ++i) teleop_.handleKey('z', 0.0);
  EXPECT_EQ(teleop_.step(), 0.001);
  EXPECT_TRUE(teleop_.handleKey('i', 0.0).target.isApprox(Vec3(1.001, 1, 1), 1e-12));
}

TEST_F(PinTeleopTest, CtrlCAndCtrlDQuitOtherKeysDoNothing) {
  EXPECT_TRUE(teleop_.handleKey(3, 0.0).quit);
  EXPECT_TRUE(teleop_.handleKey(4, 0.0).quit);
  const TeleopAction a = teleop_.handleKey('x', 0.0);
  EXPECT_FALSE(a.quit);
  EXPECT_FALSE(a.publish);
  EXPECT_NE(a.status.find("unknown key"), std::string::npos);
}

TEST_F(PinTeleopTest, ARemovedSelectedPinMovesTheSelection) {
  teleop_.handleKey('n', 0.0);  // 5
  teleop_.updatePins({{7, Vec3(0, 0, 1)}, {2, Vec3(1, 1, 1)}}, 1.0);
  EXPECT_EQ(teleop_.selectedPin(), 2);
  teleop_.updatePins({}, 2.0);
  EXPECT_EQ(teleop_.selectedPin(), -1);
}

TEST(PinTeleop, RefusesAStepOutOfRange) {
  EXPECT_THROW(PinTeleop(0.0), std::invalid_argument);
  EXPECT_THROW(PinTeleop(2.0), std::invalid_argument);
}

TEST(PinTeleop, HelpListsEveryKey) {
  const std::string help = PinTeleop::help();
  for (const char* key : {"i / ,", "j / l", "t / b", "k ", "n / p", "q / z", "CTRL-C"}) {
    EXPECT_NE(help.find(key), std::string::npos) << key;
  }
}

}  // namespace
}  // namespace cloth_sim::node
