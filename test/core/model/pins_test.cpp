#include <gtest/gtest.h>

#include "cloth_sim/core/model/pins.h"

namespace cloth_sim {
namespace {

TEST(PinSet, StableIdsAndLookup) {
  PinSet pins;
  const int a = pins.add(3, Vec3(1, 2, 3), 0.0, 10);
  const int b = pins.add(5, Vec3::Zero(), 50.0, 10);
  EXPECT_NE(a, b);
  pins.remove(a);
  const int c = pins.add(3, Vec3::Zero(), 0.0, 10);
  EXPECT_NE(c, a);  // ids are never reused
  ASSERT_NE(pins.find(b), nullptr);
  EXPECT_EQ(pins.find(b)->vertex, 5);
  EXPECT_FALSE(pins.find(b)->isHard());
  EXPECT_EQ(pins.findByVertex(3)->id, c);
  EXPECT_EQ(pins.find(a), nullptr);
}

TEST(PinSet, RefusesBadInputAndStaysUntouched) {
  PinSet pins;
  pins.add(0, Vec3::Zero(), 0.0, 4);
  EXPECT_THROW(pins.add(4, Vec3::Zero(), 0.0, 4), std::invalid_argument);   // out of range
  EXPECT_THROW(pins.add(-1, Vec3::Zero(), 0.0, 4), std::invalid_argument);
  EXPECT_THROW(pins.add(0, Vec3::Zero(), 0.0, 4), std::invalid_argument);   // already pinned
  EXPECT_THROW(pins.add(1, Vec3(NAN, 0, 0), 0.0, 4), std::invalid_argument);
  EXPECT_THROW(pins.add(1, Vec3::Zero(), -2.0, 4), std::invalid_argument);
  EXPECT_THROW(pins.remove(42), std::invalid_argument);
  EXPECT_THROW(pins.moveTarget(42, Vec3::Zero()), std::invalid_argument);
  EXPECT_THROW(pins.moveTarget(0, Vec3(0, INFINITY, 0)), std::invalid_argument);
  EXPECT_EQ(pins.size(), 1u);
  EXPECT_EQ(pins.pins()[0].target, Vec3::Zero());
  try {
    pins.add(9, Vec3::Zero(), 0.0, 4);
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("out of range [0, 4)"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace cloth_sim
