// NodeOptions: parsing from the private namespace, validation and scene loading, no master.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <string>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>

#include "cloth_sim/node/options.h"
#include "error_of.h"

namespace cloth_sim::node {
namespace {

const std::string kSceneDir = std::string(CLOTH_SIM_SOURCE_DIR) + "/config/scenes";

XmlRpc::XmlRpcValue params(const std::string& scene = "hanging") {
  XmlRpc::XmlRpcValue p;
  p["scene"] = scene;
  return p;
}

/// The message parseNodeOptions throws for @p p, or "" when it accepts it.
std::string parseError(const XmlRpc::XmlRpcValue& p) {
  return test::errorOf([&] { parseNodeOptions(p); });
}

/// The message loadScene throws for a ~scene of @p scene, or "" when it loads.
std::string loadError(const std::string& scene) {
  NodeOptions o;
  o.scene = scene;
  return test::errorOf([&] { loadScene(o, kSceneDir); });
}

TEST(NodeOptions, DefaultsWhenOnlyTheSceneIsGiven) {
  const NodeOptions o = parseNodeOptions(params());
  EXPECT_EQ(o.scene, "hanging");
  EXPECT_EQ(o.frame_id, "world");
  EXPECT_EQ(o.render_rate, 30.0);
  EXPECT_EQ(o.solver, "");
  EXPECT_EQ(o.iterations, 0);
  EXPECT_EQ(o.max_rollbacks, 30);
  EXPECT_TRUE(o.shading);
  EXPECT_EQ(o.max_interactive_pins, 16);
  EXPECT_EQ(o.summary_period, 0.0);
}

TEST(NodeOptions, ReadsEveryParameterAndAcceptsAnIntegerForANumber) {
  XmlRpc::XmlRpcValue p = params("drape");
  p["frame_id"] = "odom";
  p["render_rate"] = 12;  // an int where a double is expected: fine
  p["solver"] = "chebyshev";
  p["iterations"] = 25;
  p["max_rollbacks"] = 5;
  p["strain_color_scale"] = 0.2;
  p["shading"] = false;
  p["sphere_cull_distance"] = 7.5;
  p["max_interactive_pins"] = 0;
  p["summary_period"] = 2.0;
  p["structural_stiffness"] = 10.0;  // a dynamic_reconfigure parameter: not ours, left alone
  const NodeOptions o = parseNodeOptions(p);
  EXPECT_EQ(o.scene, "drape");
  EXPECT_EQ(o.frame_id, "odom");
  EXPECT_EQ(o.render_rate, 12.0);
  EXPECT_EQ(o.solver, "chebyshev");
  EXPECT_EQ(o.iterations, 25);
  EXPECT_EQ(o.max_rollbacks, 5);
  EXPECT_EQ(o.strain_color_scale, 0.2);
  EXPECT_FALSE(o.shading);
  EXPECT_EQ(o.sphere_cull_distance, 7.5);
  EXPECT_EQ(o.max_interactive_pins, 0);
  EXPECT_EQ(o.summary_period, 2.0);
}

TEST(NodeOptions, SimulatedTimeAndGraspParameters) {
  const NodeOptions defaults = parseNodeOptions(params());
  EXPECT_FALSE(defaults.publish_clock);
  EXPECT_EQ(defaults.real_time_factor, 1.0);
  EXPECT_FALSE(defaults.start_paused);
  EXPECT_EQ(defaults.grasp_frame_timeout, 0.5);
  EXPECT_EQ(defaults.force_arrow_scale, 0.5);
  EXPECT_EQ(defaults.budget_ms, 0.0);
  XmlRpc::XmlRpcValue p = params();
  p["budget_ms"] = 8.3;
  p["publish_clock"] = true;
  p["real_time_factor"] = 0;  // an int: as fast as possible
  p["start_paused"] = true;
  p["grasp_frame_timeout"] = 2.0;
  p["force_arrow_scale"] = 0.0;
  const NodeOptions o = parseNodeOptions(p);
  EXPECT_TRUE(o.publish_clock);
  EXPECT_EQ(o.real_time_factor, 0.0);
  EXPECT_TRUE(o.start_paused);
  EXPECT_EQ(o.grasp_frame_timeout, 2.0);
  EXPECT_EQ(o.force_arrow_scale, 0.0);
  EXPECT_EQ(o.budget_ms, 8.3);
  for (const auto& [param, value, message] :
       {std::tuple{"real_time_factor", -1.0, "parameter '~real_time_factor': -1 must be in [0, 1000] (0 = as fast as possible)"},
        std::tuple{"real_time_factor", 1e9, "parameter '~real_time_factor': 1e+09 must be in [0, 1000]"},
        std::tuple{"grasp_frame_timeout", 0.0, "parameter '~grasp_frame_timeout': 0 must be finite and > 0 s"},
        std::tuple{"budget_ms", -1.0, "parameter '~budget_ms': -1 must be in [0, 1000] ms (0 = off)"},
        std::tuple{"budget_ms", std::nan(""), "parameter '~budget_ms': nan must be in [0, 1000] ms (0 = off)"},
        std::tuple{"force_arrow_scale", -0.1, "parameter '~force_arrow_scale': -0.1 must be finite and >= 0 m/N"}}) {
    XmlRpc::XmlRpcValue bad = params();
    bad[param] = value;
    EXPECT_NE(parseError(bad).find(message), std::string::npos) << parseError(bad);
  }
}

TEST(NodeOptions, RobotAndTfBufferParameters) {
  const NodeOptions defaults = parseNodeOptions(params());
  EXPECT_EQ(defaults.tf_buffer_duration, 120.0);
  EXPECT_TRUE(defaults.robot_links.empty());
  XmlRpc::XmlRpcValue p = params();
  p["tf_buffer_duration"] = 30;
  p["robot_links"] = "finger_upper, finger_lower  palm";
  p["robot_margin"] = 0.002;
  p["robot_friction"] = 1.5;
  const NodeOptions o = parseNodeOptions(p);
  EXPECT_EQ(o.tf_buffer_duration, 30.0);
  EXPECT_EQ(o.robot_links, (std::vector<std::string>{"finger_upper", "finger_lower", "palm"}));
  EXPECT_EQ(o.robot_margin, 0.002);
  EXPECT_EQ(o.robot_friction, 1.5);
  XmlRpc::XmlRpcValue list;
  list[0] = "a";
  list[1] = "b";
  p["robot_links"] = list;
  EXPECT_EQ(parseNodeOptions(p).robot_links, (std::vector<std::string>{"a", "b"}));
  list[1] = 3;
  p["robot_links"] = list;
  EXPECT_EQ(parseError(p), "parameter '~robot_links': expected a list of names, got an integer");
  p = params();
  p["tf_buffer_duration"] = 0.5;
  EXPECT_EQ(parseError(p), "parameter '~tf_buffer_duration': 0.5 must be in [1, 3600] s");
  p = params();
  p["robot_margin"] = 0.0;
  EXPECT_EQ(parseError(p), "parameter '~robot_margin': 0 must be in (0, 1] m");
  p = params();
  p["robot_friction"] = -1;
  EXPECT_EQ(parseError(p), "parameter '~robot_friction': -1 must be in [0, 100]");
}

TEST(NodeOptions, AMissingSceneIsRefusedNamingTheParameter) {
  const std::string e = parseError(XmlRpc::XmlRpcValue());  // empty private namespace
  EXPECT_NE(e.find("parameter '~scene'"), std::string::npos) << e;
  EXPECT_NE(e.find("required"), std::string::npos) << e;
}

TEST(NodeOptions, AWrongTypeIsRefusedNamingParameterAndTypes) {
  XmlRpc::XmlRpcValue p = params();
  p["render_rate"] = "fast";
  const std::string e = parseError(p);
  EXPECT_NE(e.find("parameter '~render_rate'"), std::string::npos) << e;
  EXPECT_NE(e.find("expected a number, got a string"), std::string::npos) << e;

  p = params();
  p["shading"] = 1;
  EXPECT_NE(parseError(p).find("parameter '~shading': expected true or false"), std::string::npos);
  p = params();
  p["iterations"] = 2.5;
  EXPECT_NE(parseError(p).find("parameter '~iterations': expected an integer, got a number"),
            std::string::npos);
}

TEST(NodeOptions, ANamespaceThatIsNotAMapIsRefused) {
  EXPECT_NE(parseError(XmlRpc::XmlRpcValue(3)), "");
}

/// One bad value per rule, with the parameter the message must name.
struct BadValue {
  const char* param;
  XmlRpc::XmlRpcValue value;
  const char* rule;  ///< a piece of the message
};

TEST(NodeOptions, EveryRuleIsCheckedAndNamesItsParameter) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const BadValue cases[] = {
      {"render_rate", XmlRpc::XmlRpcValue(-3.0), "-3 must be in (0, 1000] Hz"},
      {"render_rate", XmlRpc::XmlRpcValue(0.0), "must be in (0, 1000] Hz"},
      {"render_rate", XmlRpc::XmlRpcValue(2000.0), "must be in (0, 1000] Hz"},
      {"render_rate", XmlRpc::XmlRpcValue(nan), "must be in (0, 1000] Hz"},
      {"frame_id", XmlRpc::XmlRpcValue("/world"), "without a leading '/'"},
      {"frame_id", XmlRpc::XmlRpcValue(""), "non-empty"},
      {"solver", XmlRpc::XmlRpcValue("runge_kutta"), "local_global"},  // lists the valid names
      {"iterations", XmlRpc::XmlRpcValue(-1), "must be in [0, 100000]"},
      {"substeps", XmlRpc::XmlRpcValue(-1), "must be in [0, 1000]"},
      {"substeps", XmlRpc::XmlRpcValue(1001), "must be in [0, 1000]"},
      {"max_rollbacks", XmlRpc::XmlRpcValue(0), "must be >= 1"},
      {"strain_color_scale", XmlRpc::XmlRpcValue(0.0), "must be finite and > 0"},
      {"sphere_cull_distance", XmlRpc::XmlRpcValue(-1.0), "must be finite and > 0"},
      {"max_interactive_pins", XmlRpc::XmlRpcValue(-1), "must be >= 0"},
      {"summary_period", XmlRpc::XmlRpcValue(-0.5), "must be finite and >= 0"},
      {"marker_bandwidth", XmlRpc::XmlRpcValue(0.0), "must be finite and > 0 bytes/s"},
      {"color_mode", XmlRpc::XmlRpcValue("red"), "color mode 'red' must be 'strain' or 'shaded'"},
  };
  for (const BadValue& c : cases) {
    XmlRpc::XmlRpcValue p = params();
    p[c.param] = c.value;
    const std::string e = parseError(p);
    EXPECT_NE(e.find(std::string("parameter '~") + c.param + "'"), std::string::npos)
        << c.param << ": " << e;
    EXPECT_NE(e.find(c.rule), std::string::npos) << c.param << ": " << e;
  }
}

TEST(ResolveScenePath, ABareNameIsAShippedSceneAnythingElseIsAPath) {
  EXPECT_EQ(resolveScenePath("drape", "/pkg/config/scenes"), "/pkg/config/scenes/drape.yaml");
  EXPECT_EQ(resolveScenePath("/tmp/my.yaml", "/d"), "/tmp/my.yaml");
  EXPECT_EQ(resolveScenePath("rel/my.yaml", "/d"), "rel/my.yaml");
  EXPECT_EQ(resolveScenePath("my.yaml", "/d"), "my.yaml");
}

TEST(LoadScene, LoadsAShippedSceneByNameAndAppliesTheOverrides) {
  NodeOptions o;
  o.scene = "hanging";
  SceneConfig scene = loadScene(o, kSceneDir);
  EXPECT_EQ(scene.grid.rows, 32);
  EXPECT_EQ(scene.options.solver, "local_global");
  EXPECT_EQ(scene.options.settings.max_iterations, 3);  // hanging.yaml
  EXPECT_EQ(scene.options.settings.substeps, 32);

  o.solver = "chebyshev";
  o.iterations = 40;
  o.substeps = 3;
  scene = loadScene(o, kSceneDir);
  EXPECT_EQ(scene.options.solver, "chebyshev");
  EXPECT_EQ(scene.options.settings.max_iterations, 40);
  EXPECT_EQ(scene.options.settings.substeps, 3);
}

TEST(LoadScene, SelfCollisionParameterOverridesTheScene) {
  XmlRpc::XmlRpcValue p = params("fold");
  EXPECT_FALSE(parseNodeOptions(p).self_collision.has_value());  // unset: the scene's
  EXPECT_TRUE(loadScene(parseNodeOptions(p), kSceneDir).options.self_contact.enabled);
  p["self_collision"] = false;
  EXPECT_FALSE(loadScene(parseNodeOptions(p), kSceneDir).options.self_contact.enabled);
  p = params("hanging");
  p["self_collision"] = true;
  const SceneConfig on = loadScene(parseNodeOptions(p), kSceneDir);
  EXPECT_TRUE(on.options.self_contact.enabled);
  EXPECT_EQ(on.options.self_contact.thickness, 0.0);  // automatic
  p["self_collision"] = "yes";
  EXPECT_NE(parseError(p).find("self_collision"), std::string::npos) << parseError(p);
}

TEST(LoadScene, AMissingFileIsRefusedNamingTheParameterAndThePath) {
  const std::string m = loadError("no_such_scene");
  EXPECT_NE(m.find("parameter '~scene'"), std::string::npos) << m;
  EXPECT_NE(m.find("no_such_scene.yaml"), std::string::npos) << m;
}

TEST(LoadScene, EveryShippedSceneLoadsByNameAndAnUnknownNameListsThem) {
  const std::vector<std::string> shipped = shippedScenes(kSceneDir);
  EXPECT_GE(shipped.size(), 10u);  // config/scenes/ as of this test: hanging ... grasp_demo
  EXPECT_TRUE(std::is_sorted(shipped.begin(), shipped.end()));
  const std::string m = loadError("no_such_scene");
  for (const std::string& name : shipped) {
    EXPECT_EQ(loadError(name), "") << name;
    EXPECT_NE(m.find(name), std::string::npos) << name << " not listed in: " << m;
  }
  EXPECT_EQ(loadError("/nonexistent/x.yaml").find("shipped"), std::string::npos);  // a path
}

TEST(LoadScene, AnInvalidFileIsRefusedNamingTheParameterAndTheField) {
  const std::string path = ::testing::TempDir() + "cloth_sim_bad_scene.yaml";
  std::ofstream(path) << "cloth:\n  grid:\n    rows: -3\n    cols: 4\n    size: [1, 1]\n"
                         "material:\n  springs:\n    structural: 100\n";
  const std::string m = loadError(path);
  EXPECT_NE(m.find("parameter '~scene'"), std::string::npos) << m;
  EXPECT_NE(m.find("cloth.grid.rows"), std::string::npos) << m;
  std::remove(path.c_str());
}

}  // namespace
}  // namespace cloth_sim::node
