// The pinch through a real master (pinch.test, pinch_slip.test): the URDF gripper's two box
// fingers (~robot_links, their tf frames published ahead here) close on the edge of the cloth
// lying on the table of config/scenes/pinch.yaml and lift. No grasp service: friction alone holds
// it. With ~robot_friction 1 the cloth's centre of mass rises with the fingers (within 1 cm once
// it hangs free); with 0.1 it slips out (~expect_hold tells which this launch checks).
#include <gtest/gtest.h>

#include <cloth_sim/FrameState.h>
#include <cloth_sim/GetState.h>

#include "robot_util.h"

namespace cloth_sim::test {
namespace {

constexpr double kTop = 0.75, kX = 0.33, kGap = 0.009;  // table top, fingers' x, closed gap (m)

double smooth(double s) {
  s = std::clamp(s, 0.0, 1.0);
  return s * s * (3.0 - 2.0 * s);
}
/// The gripper lifts 0.5 m between t = 2 s and 4 s.
double lift(double t) { return 0.5 * smooth((t - 2.0) / 2.0); }
/// The finger frames of config/robots/parallel_gripper.urdf: finger_lower's at its box's upper
/// face, finger_upper's at its box's lower face. The lower jaw lies flush with the table top
/// under the overhanging edge; the upper one closes from 8 cm to the gap by t = 1.5 s.
Eigen::Isometry3d lowerFinger(double t) { return at(kX, 0.0, kTop + lift(t)); }
Eigen::Isometry3d upperFinger(double t) {
  return at(kX, 0.0, kTop + lift(t) + kGap + 0.08 * (1.0 - smooth((t - 0.5) / 1.0)));
}

double meanHeight(const FrameState& f) {
  double sum = 0.0;
  for (std::size_t i = 2; i < f.positions.size(); i += 3) sum += f.positions[i];
  return sum / static_cast<double>(f.positions.size() / 3);
}

TEST(Pinch, TheFingersLiftTheClothByFrictionOrLetItSlip) {
  bool expect_hold = true;
  ros::NodeHandle("~").getParam("expect_hold", expect_hold);
  const ros::Time origin = simOrigin();
  ASSERT_DOUBLE_EQ(step(0).sim_time, 0.0);
  publishAhead(origin, 0.0, 5.1, 1.0 / 480.0,
               {{"finger_lower", lowerFinger}, {"finger_upper", upperFinger}});
  const GetState::Response start = call<GetState>(names::kGetState, GetState::Request());
  ASSERT_EQ(start.colliders.size(), 3u);  // the table and the two fingers
  Collector<FrameState> frames(names::kFrameState);
  wallSleep(1.0);
  step(300);  // 5 s
  ASSERT_TRUE(frames.waitForCount(300));
  double com_free = NAN, com_end = NAN;
  for (const FrameState& f : frames.all()) {
    if (std::abs(f.sim_time - 3.2) < 1e-6) com_free = meanHeight(f);  // hanging free by now
    if (std::abs(f.sim_time - 5.0) < 1e-6) com_end = meanHeight(f);
  }
  ASSERT_TRUE(std::isfinite(com_free) && std::isfinite(com_end));
  const double finger_rise = lift(5.0) - lift(3.2), com_rise = com_end - com_free;
  std::printf("[measured] pinch (%s): fingers rose %.4f m from 3.2 s to 5 s, the cloth's centre of "
              "mass %.4f m; it ends %.3f m above the table\n",
              expect_hold ? "expect hold" : "expect slip", finger_rise, com_rise, com_end - kTop);
  if (expect_hold) {
    EXPECT_NEAR(com_rise, finger_rise, 0.01);
    EXPECT_GT(com_end - kTop, 0.2);
  } else {
    EXPECT_LT(com_end - kTop, 0.05);  // not carried
  }
}

}  // namespace
}  // namespace cloth_sim::test

int main(int argc, char** argv) { return cloth_sim::test::runRosTests(argc, argv, "pinch_test"); }
