// The size of a cloth/markers array against the cloth's size, and the pacing that
// keeps the markers under ~marker_bandwidth bytes per second (an 81 x 81 cloth was 1.54 MB an
// array, 46 MB/s at 30 Hz). The [measured] lines are the table of docs/ros_interface.md.
#include <cstdio>
#include <vector>

#include <gtest/gtest.h>
#include <ros/serialization.h>

#include "cloth_sim/core/model/grid_builder.h"
#include "cloth_sim/node/marker_builder.h"
#include "cloth_sim/node/options.h"
#include "cloth_sim/node/render_pacer.h"

namespace cloth_sim::node {
namespace {

/// Bytes of the cloth/markers array of an n x n grid with two pins (what the node sends).
std::size_t arrayBytes(int n) {
  GridSpec spec;
  spec.rows = spec.cols = n;
  const BuiltObject grid = buildGrid(spec);
  const Eigen::VectorXd strain = Eigen::VectorXd::Zero(grid.rest_positions.cols());
  std::vector<Pin> pins(2);
  pins[1].id = 1;
  pins[1].vertex = n - 1;
  const std::vector<SphereCollider> spheres;
  const MarkerScene scene{grid.rest_positions, grid.model.triangles, strain, pins, spheres,
                          GroundPlane{}};
  std_msgs::Header header;
  header.frame_id = "world";
  const MarkerBuild build = buildMarkers(scene, MarkerStyle{}, header, ShownMarkers{});
  return ros::serialization::serializationLength(build.markers);
}

/// Bytes per second a pacer lets through over @p seconds of ticks, for arrays of @p bytes.
double paced(RenderPacer pacer, double tick, std::size_t bytes, double seconds) {
  std::size_t total = 0;
  for (double t = 0.0; t < seconds; t += tick) {
    if (!pacer.due(t)) continue;
    pacer.sent(t, bytes);
    total += bytes;
  }
  return total / seconds;
}

TEST(MarkerBytes, GrowWithTheTrianglesAndThePacerKeepsThemUnderTheBudget) {
  const NodeOptions defaults;
  const double tick = 1.0 / defaults.render_rate;
  const RenderPacer pacer(defaults.marker_bandwidth, tick);
  std::printf("[measured] | cloth | triangles | bytes per array | Hz at ~render_rate 30 | "
              "MB/s |\n");
  for (int n : {16, 32, 40, 49, 64, 81, 128}) {
    const std::size_t bytes = arrayBytes(n);
    const std::size_t corners = 6 * static_cast<std::size_t>(n - 1) * (n - 1);
    // A point (3 float64) and a colour (4 float32) per triangle corner, plus a little.
    EXPECT_GE(bytes, 40 * corners);
    EXPECT_LE(bytes, 40 * corners + 2000) << n;
    const double rate = pacer.rateFor(bytes);
    std::printf("[measured] | %d x %d | %zu | %zu | %.1f | %.1f |\n", n, n, corners / 3, bytes,
                rate, rate * bytes / 1e6);
    const double per_second = paced(pacer, tick, bytes, 20.0);
    // Within the timer's slack, plus the one array that starts the count.
    EXPECT_LE(per_second, (1 + RenderPacer::kSlack) * defaults.marker_bandwidth + bytes / 20.0)
        << n;
    EXPECT_NEAR(per_second / bytes, rate, 0.1) << n;
    if (n <= 40) EXPECT_NEAR(rate, defaults.render_rate, 1e-9) << n;  // small: every tick
  }
  // The figure: an 81 x 81 array of 1.54 MB now goes at 7.5 Hz, under 12 MB/s.
  EXPECT_NEAR(arrayBytes(81) / 1e6, 1.54, 0.01);
  EXPECT_LT(pacer.rateFor(arrayBytes(81)) * arrayBytes(81), defaults.marker_bandwidth);
}

TEST(RenderPacer, EveryTickWhileSmallAndATimerFiringEarlyLosesNoTick) {
  RenderPacer pacer(1e6, 0.1);
  EXPECT_TRUE(pacer.due(0.0));
  pacer.sent(0.0, 1000);  // 1 ms of budget: due again at the next tick
  EXPECT_TRUE(pacer.due(0.099));
  pacer.sent(0.1, 250000);  // 0.25 s of budget: the ticks at 0.2 and 0.3 wait
  EXPECT_FALSE(pacer.due(0.2));
  EXPECT_FALSE(pacer.due(0.3));
  EXPECT_TRUE(pacer.due(0.4));  // every third tick
  EXPECT_TRUE(pacer.due(0.345));  // a tick firing up to 5 ms early still counts
  EXPECT_DOUBLE_EQ(pacer.rateFor(1000), 10.0);
  EXPECT_DOUBLE_EQ(pacer.rateFor(250000), 10.0 / 3.0);
}

}  // namespace
}  // namespace cloth_sim::node
