// dynamic_reconfigure on a running cloth_sim_node: a stiffness change changes the sag the right
// way, solver and iterations switch, a refused value is put back, and an unstable solver leads
// to rollbacks, automatic resets and an ERROR in /diagnostics, with finite markers throughout.
#include <algorithm>
#include <cmath>

#include <diagnostic_msgs/DiagnosticArray.h>
#include <dynamic_reconfigure/Reconfigure.h>
#include <gtest/gtest.h>

#include <cloth_sim/AddPin.h>
#include <cloth_sim/SpawnSphere.h>

#include "ros_test_util.h"

namespace cloth_sim::test {
namespace {

const std::string kSetParameters = names::setParameters();

NodeProbe& probe() {
  static NodeProbe p{ros::NodeHandle()};
  static const bool ready = p.waitForTraffic(60.0);
  EXPECT_TRUE(ready) << "no cloth/state or cloth/markers within 60 s";
  return p;
}

/// Sets one parameter (a member of @p list, e.g. &Config::doubles) through the node's
/// set_parameters service; returns the config the node reports back.
template <class Param, class Value>
dynamic_reconfigure::Config reconfigure(std::vector<Param> dynamic_reconfigure::Config::*list,
                                        const std::string& name, const Value& value) {
  dynamic_reconfigure::Reconfigure::Request req;
  Param p;
  p.name = name;
  p.value = value;
  (req.config.*list).push_back(p);
  return call<dynamic_reconfigure::Reconfigure>(kSetParameters, req).config;
}
dynamic_reconfigure::Config reconfigure(const std::string& name, double value) {
  return reconfigure(&dynamic_reconfigure::Config::doubles, name, value);
}
dynamic_reconfigure::Config reconfigure(const std::string& name, int value) {
  return reconfigure(&dynamic_reconfigure::Config::ints, name, value);
}
dynamic_reconfigure::Config reconfigure(const std::string& name, const std::string& value) {
  return reconfigure(&dynamic_reconfigure::Config::strs, name, value);
}

double doubleIn(const dynamic_reconfigure::Config& c, const std::string& name) {
  for (const auto& d : c.doubles) {
    if (d.name == name) return d.value;
  }
  ADD_FAILURE() << name << " not in the reported config";
  return NAN;
}

/// Lowest point of the sheet (m), averaged over the markers of @p seconds.
double lowestPoint(double seconds) {
  const auto arrays = probe().collectMarkers(seconds);
  EXPECT_GE(arrays.size(), 5u);
  double sum = 0.0;
  for (const auto& a : arrays) {
    const auto* cloth = findMarker(a, names::kClothNs, 0);
    double low = INFINITY;
    for (const auto& pt : cloth->points) low = std::min(low, pt.z);
    sum += low;
  }
  return sum / arrays.size();
}

constexpr double kSettle = 3.0;  // s; damping 3/s: the sheet settles well within this

TEST(Reconfigure, StiffnessChangesTheSagTheRightWay) {
  probe();
  ros::WallDuration(kSettle).sleep();
  const double z_50 = lowestPoint(0.5);

  EXPECT_EQ(doubleIn(reconfigure("structural_stiffness", 10.0), "structural_stiffness"), 10.0);
  ros::WallDuration(kSettle).sleep();
  const double z_10 = lowestPoint(0.5);

  EXPECT_EQ(doubleIn(reconfigure("structural_stiffness", 500.0), "structural_stiffness"), 500.0);
  ros::WallDuration(kSettle).sleep();
  const double z_500 = lowestPoint(0.5);

  std::printf("[measured] lowest point: %.4f m at 50 N/m, %.4f m at 10 N/m, %.4f m at 500 N/m\n",
              z_50, z_10, z_500);
  EXPECT_LT(z_10, z_50 - 0.01) << "softer springs must sag more";
  EXPECT_GT(z_500, z_50 + 0.003) << "stiffer springs must sag less";
}

TEST(Reconfigure, SolverAndIterationsSwitchAndARefusedValueIsPutBack) {
  NodeProbe& p = probe();
  reconfigure("solver", std::string("chebyshev"));
  reconfigure("iterations", 25);
  const auto s = p.waitForState(
      [](const ClothState& c) { return c.solver == "chebyshev" && c.iterations == 25; }, 3.0);
  EXPECT_TRUE(s) << "the node still steps with " << p.latestState().solver << ", "
                 << p.latestState().iterations << " iterations";

  // The sheet has no bending springs: the value is refused and the server reports it back at 0.
  EXPECT_EQ(doubleIn(reconfigure("bending_stiffness", 7.0), "bending_stiffness"), 0.0);
  EXPECT_TRUE(p.waitForLog("this object has no bending springs", 5.0));

  reconfigure("solver", std::string("local_global"));
  reconfigure("iterations", 10);
  EXPECT_TRUE(p.waitForState(
      [](const ClothState& c) { return c.solver == "local_global" && c.iterations == 10; }, 3.0));
}

TEST(Reconfigure, SubstepsSplitTheFrameWhichStaysTheStep) {
  NodeProbe& p = probe();
  const double frame = p.latestState().time_step;
  reconfigure("substeps", 4);
  EXPECT_TRUE(p.waitForState(
      [frame](const ClothState& c) { return c.substeps == 4 && c.time_step == frame; }, 3.0))
      << "the node still steps with " << p.latestState().substeps << " substeps";
  reconfigure("substeps", 1);
  EXPECT_TRUE(p.waitForState([](const ClothState& c) { return c.substeps == 1; }, 3.0));
}

TEST(Reconfigure, AFrameBudgetPicksTheSubstepsAndOffLeavesThemAlone) {
  NodeProbe& p = probe();
  // 400 substeps of 10 iterations cost far more than 0.3 ms on any machine: the budget must
  // bring them down within a few frames (the first frame after a change is not counted).
  reconfigure("substeps", 400);
  ASSERT_TRUE(p.waitForState([](const ClothState& c) { return c.substeps == 400; }, 5.0));
  EXPECT_EQ(doubleIn(reconfigure("budget_ms", 0.3), "budget_ms"), 0.3);
  const auto fitted = p.waitForState([](const ClothState& c) { return c.substeps < 400; }, 5.0);
  ASSERT_TRUE(fitted) << "still " << p.latestState().substeps << " substeps";
  // Off: the configured 400 substeps come back (the budget's choice was left in place), and
  // then they stay what the user sets.
  EXPECT_EQ(doubleIn(reconfigure("budget_ms", 0.0), "budget_ms"), 0.0);
  EXPECT_TRUE(p.waitForState([](const ClothState& c) { return c.substeps == 400; }, 5.0))
      << "still " << p.latestState().substeps << " substeps";
  // A budget longer than the 16.7 ms frame is refused; the server reports 0, the value kept.
  EXPECT_EQ(doubleIn(reconfigure("budget_ms", 100.0), "budget_ms"), 0.0);
  EXPECT_TRUE(p.waitForLog("budget_ms 100 must be at most the frame", 5.0));
  reconfigure("substeps", 1);
  ASSERT_TRUE(p.waitForState([](const ClothState& c) { return c.substeps == 1; }, 3.0));
  for (const ClothState& c : p.collectStates(1.5)) EXPECT_EQ(c.substeps, 1);
  // A generous budget lets them grow (by a quarter at most, after half a second under it).
  reconfigure("budget_ms", 16.0);
  EXPECT_TRUE(p.waitForState([](const ClothState& c) { return c.substeps > 1; }, 5.0))
      << "still " << p.latestState().substeps << " substeps";
  reconfigure("budget_ms", 0.0);
  reconfigure("substeps", 1);
  EXPECT_TRUE(p.waitForState([](const ClothState& c) { return c.substeps == 1; }, 3.0));
}

std::string strIn(const dynamic_reconfigure::Config& c, const std::string& name) {
  for (const auto& p : c.strs) {
    if (p.name == name) return p.value;
  }
  ADD_FAILURE() << name << " not in the reported config";
  return "";
}

TEST(Reconfigure, ColorModeSwitchesAndAnUnknownOneIsPutBack) {
  // A shaded colour mode beside strain (drape's stretched cloth read as a red ball).
  probe();
  EXPECT_EQ(strIn(reconfigure("color_mode", std::string("shaded")), "color_mode"), "shaded");
  EXPECT_EQ(strIn(reconfigure("color_mode", std::string("red")), "color_mode"), "shaded");
  EXPECT_EQ(strIn(reconfigure("color_mode", std::string("strain")), "color_mode"), "strain");
}

TEST(Reconfigure, AnUnstableSolverIsRolledBackThenResetAndDiagnosed) {
  NodeProbe& p = probe();
  ros::NodeHandle nh;
  std::mutex mutex;
  int worst_level = 0;
  std::string worst_message;
  ros::Subscriber diag = nh.subscribe<diagnostic_msgs::DiagnosticArray>(
      names::kDiagnostics, 10, [&](const diagnostic_msgs::DiagnosticArray::ConstPtr& a) {
        std::lock_guard<std::mutex> lock(mutex);
        for (const auto& s : a->status) {
          if (s.name.find(names::kDiagnosticsTask) != std::string::npos && s.level > worst_level) {
            worst_level = s.level;
            worst_message = s.message;
          }
        }
      });

  // The user's edits before the trouble: a pin on the bottom-left corner and a still sphere
  // beside the sheet. The automatic reset once wiped both.
  AddPin::Request pin_req;
  pin_req.vertex = 11 * 12;  // row 11, col 0
  const auto pin = call<AddPin>(names::kAddPin, pin_req);
  ASSERT_TRUE(pin.success) << pin.message;
  SpawnSphere::Request sphere_req;
  sphere_req.center = stamped("world", 0.0, 0.4, 1.0);
  sphere_req.radius = 0.05;
  const auto sphere = call<SpawnSphere>(names::kSpawnSphere, sphere_req);
  ASSERT_TRUE(sphere.success) << sphere.message;

  // Explicit Euler with 500 N/m springs: h omega is far above 2, every step blows up.
  reconfigure("solver", std::string("explicit_euler"));
  const auto failed = p.waitForState([](const ClothState& c) { return c.status != "ok"; }, 5.0);
  ASSERT_TRUE(failed) << "explicit_euler did not diverge";
  EXPECT_FALSE(failed->message.empty());
  const auto reset = p.waitForState([](const ClothState& c) { return c.divergence_resets > 0; },
                                    10.0);
  ASSERT_TRUE(reset) << "no automatic reset after repeated rollbacks";
  const auto has_pin = [&](const ClothState& c) {
    return std::any_of(c.pins.begin(), c.pins.end(), [&](const PinInfo& i) {
      return i.id == pin.id && i.vertex == pin_req.vertex;
    });
  };
  EXPECT_TRUE(has_pin(*reset)) << "the user's pin did not survive the automatic reset";
  ASSERT_EQ(reset->spheres.size(), 1u) << "the user's sphere did not survive the automatic reset";
  EXPECT_EQ(reset->spheres[0].id, sphere.id);
  EXPECT_TRUE(p.waitForLog("pins and spheres kept", 5.0));
  for (const auto& a : p.collectMarkers(2.0)) EXPECT_TRUE(allFinite(a));
  {
    const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(5.0);
    while (ros::WallTime::now() < end) {
      {
        std::lock_guard<std::mutex> lock(mutex);
        if (worst_level == diagnostic_msgs::DiagnosticStatus::ERROR) break;
      }
      ros::WallDuration(0.05).sleep();
    }
    std::lock_guard<std::mutex> lock(mutex);
    EXPECT_EQ(worst_level, diagnostic_msgs::DiagnosticStatus::ERROR) << worst_message;
    EXPECT_NE(worst_message.find("reset"), std::string::npos) << worst_message;
  }

  reconfigure("solver", std::string("local_global"));
  const auto recovered = p.waitForState(
      [](const ClothState& c) {
        return c.solver == "local_global" && c.status == "ok" && c.consecutive_failures == 0;
      },
      5.0);
  ASSERT_TRUE(recovered);
  EXPECT_TRUE(has_pin(*recovered));
  EXPECT_EQ(recovered->spheres.size(), 1u);
}

}  // namespace
}  // namespace cloth_sim::test

int main(int argc, char** argv) {
  return cloth_sim::test::runRosTests(argc, argv, "node_reconfigure_test");
}
