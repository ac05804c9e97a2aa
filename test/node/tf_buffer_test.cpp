// A trajectory published further ahead than ~tf_buffer_duration (tf_buffer.test: 10 s, the old
// fixed buffer) through a real master: its first samples are dropped, and a collider on it is
// held at the oldest pose the buffer kept, never the latest, with a warning in the log.
#include <gtest/gtest.h>

#include <cloth_sim/AddCollider.h>
#include <cloth_sim/GetState.h>

#include "robot_util.h"

namespace cloth_sim::test {
namespace {

TEST(TfBuffer, ALookupBeforeTheOldestTransformHoldsItAndWarns) {
  NodeProbe probe{ros::NodeHandle()};
  const ros::Time origin = simOrigin();
  const double t0 = step(0).sim_time;
  const Trajectory line = [&](double t) { return at(2.0 + 0.1 * (t - t0), 0.0, 1.0); };
  publishAhead(origin, t0, t0 + 12.0, 1.0 / 120.0, {{"arm", line}});  // 12 s into a 10 s buffer
  AddCollider::Request req;
  req.shape = "sphere";
  req.radius = 0.02;
  req.frame_id = "arm";
  ASSERT_TRUE(call<AddCollider>(names::kAddCollider, req).success);
  step(60);  // 1 s: the buffer's oldest transform is about 2 s into the trajectory
  const GetState::Response s = call<GetState>(names::kGetState, GetState::Request());
  ASSERT_EQ(s.colliders.size(), 1u);
  const double x = s.colliders[0].pose.position.x, oldest = 2.0 + 0.1 * 2.0;
  std::printf("[measured] 12 s published into a 10 s buffer, at 1 s: collider at x = %.4f m "
              "(trajectory there: %.4f m, oldest kept: about %.4f m, latest: %.4f m)\n",
              x, line(s.sim_time).translation().x(), oldest, line(t0 + 12.0).translation().x());
  EXPECT_NEAR(x, oldest, 0.02);                          // the oldest kept pose, held
  EXPECT_LT(x, line(t0 + 12.0).translation().x() - 0.5);  // never the latest
  EXPECT_TRUE(probe.waitForLog("before the oldest transform the tf buffer keeps", 20.0));
}

}  // namespace
}  // namespace cloth_sim::test

int main(int argc, char** argv) { return cloth_sim::test::runRosTests(argc, argv, "tf_buffer_test"); }
