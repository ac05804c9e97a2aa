// Randomized bad input to a running cloth_sim_node: every service (spawn_sphere,
// remove_sphere, add_pin, remove_pin), the cloth/pin_move topic, every dynamic_reconfigure
// parameter and the start parameters get NaN, infinities, huge and tiny finite values, wrong
// types and long strings, one field per case from a valid request (fixed seed, printed). Each
// case must be refused with a message naming the input, or accepted and simulated with no
// rolled-back frame; throughout, the node keeps publishing, no number it publishes is NaN, and
// the pins and spheres the test added (and did not remove) are still there.

#include <cmath>
#include <cstdio>
#include <deque>
#include <limits>
#include <map>
#include <mutex>
#include <random>
#include <set>

#include <dynamic_reconfigure/Reconfigure.h>
#include <gtest/gtest.h>

#include <cloth_sim/AddPin.h>
#include <cloth_sim/PinMove.h>
#include <cloth_sim/RemovePin.h>
#include <cloth_sim/RemoveSphere.h>
#include <cloth_sim/SpawnSphere.h>

#include "ros_test_util.h"

namespace cloth_sim::test {
namespace {

constexpr unsigned kSeed = 2026;
constexpr int kCases = 400;  ///< service, topic and reconfigure cases (start parameters apart)

NodeProbe& probe() {
  static NodeProbe p{ros::NodeHandle()};
  static const bool ready = p.waitForTraffic(60.0);
  EXPECT_TRUE(ready) << "no cloth/state or cloth/markers within 60 s";
  return p;
}

/// The doubles tried: NaN, infinities, the extremes of double, huge, tiny and ordinary values.
double randomDouble(std::mt19937& rng) {
  static const double pool[] = {std::numeric_limits<double>::quiet_NaN(),
                                std::numeric_limits<double>::infinity(),
                                -std::numeric_limits<double>::infinity(),
                                std::numeric_limits<double>::max(),
                                -std::numeric_limits<double>::max(),
                                std::numeric_limits<double>::denorm_min(),
                                1e300, -1e300, 1e9, 1e6, -1e6, 100.0, 1e-9, 1e-300, 0.0, -0.0,
                                -1.0, 0.05, 0.5, 1.0, 2.0};
  std::uniform_real_distribution<double> coin(0.0, 1.0), exponent(-320.0, 310.0);
  if (coin(rng) < 0.75) {
    return pool[std::uniform_int_distribution<std::size_t>(0, std::size(pool) - 1)(rng)];
  }
  return (coin(rng) < 0.5 ? -1.0 : 1.0) * std::pow(10.0, exponent(rng));  // log-uniform
}

int randomInt(std::mt19937& rng) {
  static const int pool[] = {std::numeric_limits<int>::min(), std::numeric_limits<int>::max(),
                             -2, -1, 0, 1, 2, 7, 1023, 1024, 99, 100000};
  return pool[std::uniform_int_distribution<std::size_t>(0, std::size(pool) - 1)(rng)];
}

std::string randomFrame(std::mt19937& rng) {
  static const std::string pool[] = {"world", "", "map", "nowhere", "/world",
                                     std::string(100000, 'f')};
  return pool[std::uniform_int_distribution<std::size_t>(0, std::size(pool) - 1)(rng)];
}

std::string show(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", v);
  return text;
}

/// Watches cloth/state for rolled-back frames and NaN, remembering the case that preceded each.
class Watch {
 public:
  explicit Watch(ros::NodeHandle nh) {
    sub_ = nh.subscribe<ClothState>(names::kState, 100, [this](const ClothState::ConstPtr& s) {
      std::lock_guard<std::mutex> lock(mutex_);
      ++states_;
      bool finite = std::isfinite(s->energy) && std::isfinite(s->max_strain);
      for (const PinInfo& p : s->pins) {
        finite = finite && std::isfinite(p.position.x + p.position.y + p.position.z);
      }
      for (const SphereInfo& b : s->spheres) {
        finite = finite && std::isfinite(b.center.x + b.center.y + b.center.z);
      }
      if (s->status != "ok" || !finite) {
        problems_.push_back("after " + last_case_ + ": status " + s->status + " " + s->message +
                            (finite ? "" : " (non-finite)"));
      }
    });
  }
  void setCase(const std::string& text) {
    std::lock_guard<std::mutex> lock(mutex_);
    last_case_ = text;
  }
  std::vector<std::string> problems() {
    std::lock_guard<std::mutex> lock(mutex_);
    return problems_;
  }
  int states() {
    std::lock_guard<std::mutex> lock(mutex_);
    return states_;
  }

 private:
  std::mutex mutex_;
  ros::Subscriber sub_;
  std::string last_case_ = "(start)";
  std::vector<std::string> problems_;
  int states_ = 0;
};

/// A refusal must name what it refuses (one of @p names) and not echo a long value whole.
void expectNamed(bool success, const std::string& message, const std::vector<std::string>& names,
                 const std::string& what) {
  if (success) return;
  bool named = false;
  for (const std::string& n : names) named = named || message.find(n) != std::string::npos;
  EXPECT_TRUE(named) << what << ": '" << message.substr(0, 300) << "' names none of the inputs";
  EXPECT_LT(message.size(), 1000u) << what << ": a long value must not be echoed whole";
}

struct Tally {
  int refused = 0, accepted = 0;
  void count(bool success) { ++(success ? accepted : refused); }
};

TEST(BadInputRandom, EveryInputRefusedByNameOrSimulatedWithoutRollback) {
  NodeProbe& p = probe();
  ros::NodeHandle nh;
  Watch watch(nh);
  ros::Publisher pin_pub = nh.advertise<PinMove>(names::kPinMove, 100);
  ASSERT_TRUE(waitForSubscriber(pin_pub));
  ClothState start = p.latestState();
  ASSERT_EQ(start.status, "ok");
  std::printf("[measured] seed %u, %d cases\n", kSeed, kCases);
  std::mt19937 rng(kSeed);
  std::uniform_int_distribution<int> pick_kind(0, 5), pick_field(0, 9);

  std::set<int> spheres, pins;  // what the test added and has not removed
  for (const PinInfo& pin : start.pins) pins.insert(pin.id);
  // The configuration in use (an empty request changes nothing and reports it).
  const dynamic_reconfigure::Config initial =
      call<dynamic_reconfigure::Reconfigure>(names::setParameters(),
                                             dynamic_reconfigure::Reconfigure::Request())
          .config;
  std::map<std::string, Tally> tally;
  for (int k = 0; k < kCases; ++k) {
    const int kind = pick_kind(rng), field = pick_field(rng);
    const double x = randomDouble(rng);
    const int n = randomInt(rng);
    const std::string frame = randomFrame(rng);
    std::string what = "case " + std::to_string(k) + ": ";
    if (kind == 0) {  // spawn_sphere: a still sphere 0.6 m above the cloth's top, one field bad
      SpawnSphere::Request r;
      r.center = stamped("world", 0.0, 0.0, 2.1);
      r.radius = 0.05;
      const std::vector<std::string> names[] = {
          {"center"}, {"center"}, {"center"}, {"radius"}, {"velocity", "speed"},
          {"velocity", "speed"}, {"mass"}, {"friction"}, {"restitution"}, {"center", "frame"}};
      switch (field) {
        case 0: r.center.point.x = x; break;
        case 1: r.center.point.y = x; break;
        case 2: r.center.point.z = x; break;
        case 3: r.radius = x; break;
        case 4: r.velocity.x = x; break;
        case 5: r.velocity.z = x; break;
        case 6: r.mass = x; break;
        case 7: r.friction = x; break;
        case 8: r.restitution = x; break;
        default: r.center.header.frame_id = frame;
      }
      what += "spawn_sphere field " + std::to_string(field) + " = " +
              (field == 9 ? frame.substr(0, 20) : show(x));
      watch.setCase(what);
      const auto res = call<SpawnSphere>(names::kSpawnSphere, r);
      expectNamed(res.success, res.message, names[field], what);
      tally["spawn_sphere"].count(res.success);
      if (res.success) spheres.insert(res.id);
    } else if (kind == 1) {  // add_pin: by vertex or nearest to a point
      AddPin::Request r;
      r.vertex = field < 3 ? -1 : n;
      r.point = stamped(field == 2 ? frame : "world", field == 0 ? x : 0.0, 0.0,
                        field == 1 ? x : 1.0);
      if (field >= 6) r.stiffness = x;
      what += "add_pin vertex " + std::to_string(r.vertex) + " point (" + show(r.point.point.x) +
              ", 0, " + show(r.point.point.z) + ") in '" + r.point.header.frame_id.substr(0, 20) +
              "' stiffness " + show(r.stiffness);
      watch.setCase(what);
      const auto res = call<AddPin>(names::kAddPin, r);
      expectNamed(res.success, res.message, {"vertex", "point", "stiffness"}, what);
      tally["add_pin"].count(res.success);
      if (res.success) pins.insert(res.id);
    } else if (kind == 2) {  // pin_move: a pin of the scene, or any id
      PinMove m;
      m.id = field < 7 ? *pins.begin() : n;
      m.target = stamped(field == 6 ? frame : "world", 0.0, 0.0, 1.0);
      if (field < 3) (field == 0 ? m.target.point.x : field == 1 ? m.target.point.y
                                                                 : m.target.point.z) = x;
      else if (field < 6) m.target.point = geometry_msgs::Point();  // the origin
      what += "pin_move id " + std::to_string(m.id) + " field " + std::to_string(field) + " = " +
              show(x);
      watch.setCase(what);
      pin_pub.publish(m);
      tally["pin_move"].count(true);  // topic: refusals are logged (checked below)
    } else if (kind == 3) {  // removals by any id
      what += (field < 5 ? "remove_sphere " : "remove_pin ") + std::to_string(n);
      watch.setCase(what);
      if (field < 5) {
        RemoveSphere::Request r;
        r.id = n;
        const auto res = call<RemoveSphere>(names::kRemoveSphere, r);
        expectNamed(res.success, res.message, {"sphere"}, what);
        EXPECT_EQ(res.success, spheres.count(n) == 1) << what;
        if (res.success) spheres.erase(n);
        tally["remove_sphere"].count(res.success);
      } else {
        RemovePin::Request r;
        r.id = n;
        const auto res = call<RemovePin>(names::kRemovePin, r);
        expectNamed(res.success, res.message, {"pin"}, what);
        EXPECT_EQ(res.success, pins.count(n) == 1) << what;
        if (res.success) pins.erase(n);
        tally["remove_pin"].count(res.success);
      }
    } else {  // dynamic_reconfigure: one parameter, then back to the scene's value
      dynamic_reconfigure::Reconfigure::Request req, back;
      static const char* const doubles[] = {"structural_stiffness", "shear_stiffness",
                                            "bending_stiffness", "damping"};
      if (field < 4) {
        dynamic_reconfigure::DoubleParameter d;
        d.name = doubles[field];
        d.value = x;
        req.config.doubles.push_back(d);
        what += std::string("reconfigure ") + d.name + " = " + show(x);
      } else if (field < 6) {
        dynamic_reconfigure::IntParameter i;
        i.name = field == 4 ? "iterations" : "substeps";
        // Within its range a huge count is accepted and slows each frame down (by design):
        // keep the accepted values small, the refused ones anything.
        i.value = n > 100 ? 0 : n;
        req.config.ints.push_back(i);
        what += "reconfigure " + i.name + " = " + std::to_string(i.value);
      } else {
        dynamic_reconfigure::StrParameter s;
        s.name = "solver";
        s.value = field == 9 ? std::string(100000, 's') : field == 8 ? "newton" : frame;
        req.config.strs.push_back(s);
        what += "reconfigure solver = " + s.value.substr(0, 20);
      }
      watch.setCase(what);
      const auto config =
          call<dynamic_reconfigure::Reconfigure>(names::setParameters(), req).config;
      for (const auto& d : config.doubles) {
        EXPECT_TRUE(std::isfinite(d.value)) << what << ": " << d.name << " reported " << d.value;
      }
      tally["reconfigure"].count(true);
      // Back to the scene's values, so that the next cases start from a known configuration.
      back.config.doubles = initial.doubles;
      back.config.ints = initial.ints;
      back.config.strs = initial.strs;
      call<dynamic_reconfigure::Reconfigure>(names::setParameters(), back);
    }
    ros::WallDuration(0.02).sleep();  // about one frame between two cases
  }

  // Everything settles (pins travelling to accepted targets, thrown spheres culled).
  const auto states = p.collectStates(2.0);
  ASSERT_GT(states.size(), 60u) << "the node stopped publishing";
  const ClothState last = states.back();
  for (int id : spheres) {
    const bool there = std::any_of(last.spheres.begin(), last.spheres.end(),
                                   [id](const SphereInfo& s) { return s.id == id; });
    // A sphere thrown out of reach is culled by the node, as documented.
    if (!there) EXPECT_TRUE(p.waitForLog("sphere " + std::to_string(id) + " removed", 0.1)) << id;
  }
  for (int id : pins) {
    EXPECT_TRUE(std::any_of(last.pins.begin(), last.pins.end(),
                            [id](const PinInfo& q) { return q.id == id; }))
        << "pin " << id << " is gone";
  }
  EXPECT_EQ(last.divergence_resets, start.divergence_resets);
  for (const auto& a : p.collectMarkers(0.5)) EXPECT_TRUE(allFinite(a));
  EXPECT_GT(p.countLogs(std::string(names::kPinMove) + ": pin"), 0);  // refused moves were logged
  const auto problems = watch.problems();
  for (std::size_t k = 0; k < std::min<std::size_t>(problems.size(), 10); ++k) {
    ADD_FAILURE() << problems[k];
  }
  EXPECT_TRUE(problems.empty()) << problems.size() << " rolled-back or non-finite frames";
  for (const auto& [name, t] : tally) {
    std::printf("[measured] %s: %d refused, %d accepted\n", name.c_str(), t.refused, t.accepted);
  }
  std::printf("[measured] %d states watched, %zu pins and %zu spheres of the test kept\n",
              watch.states(), pins.size(), spheres.size());
}

/// Runs cloth_sim_node with @p args for at most @p seconds; its exit status (124: still running
/// when stopped, i.e. it started) and output.
std::pair<int, std::string> runNode(const std::string& args, double seconds) {
  return runNodeProcess(CLOTH_SIM_NODE_EXE, args, seconds);
}

TEST(BadInputRandom, StartParametersRefusedByNameOrTheNodeRuns) {
  const char* const params[] = {"render_rate", "max_rollbacks", "strain_color_scale",
                                "sphere_cull_distance", "max_interactive_pins", "summary_period",
                                "iterations", "substeps", "solver", "frame_id"};
  constexpr unsigned kParamSeed = 7;
  constexpr int kParamCases = 10;
  std::printf("[measured] start parameters: seed %u, %d cases\n", kParamSeed, kParamCases);
  std::mt19937 rng(kParamSeed);
  std::uniform_int_distribution<std::size_t> pick(0, std::size(params) - 1);
  std::uniform_real_distribution<double> coin(0.0, 1.0);
  int refused = 0, ran = 0;
  for (int k = 0; k < kParamCases; ++k) {
    const std::string name = params[pick(rng)];
    // A number, an integer or a string (100 kB at most once in a while): rosparam's types.
    const double r = coin(rng);
    const std::string value = r < 0.4 ? show(randomDouble(rng))
                              : r < 0.7 ? std::to_string(randomInt(rng))
                              : r < 0.9 ? randomFrame(rng).substr(0, 30) : "'[1, 2]'";
    const std::string ns = "/random_param_" + std::to_string(k);
    const std::string args = "__name:=node __ns:=" + ns + " _scene:=hanging _" + name + ":=" +
                             (value.empty() ? "''" : value);
    SCOPED_TRACE("case " + std::to_string(k) + ": " + args);
    const auto [status, output] = runNode(args, 4.0);
    if (status == 124) {
      ++ran;  // started and kept running until stopped
      continue;
    }
    ++refused;
    EXPECT_EQ(status, 1) << output.substr(0, 500);
    EXPECT_NE(output.find("parameter '~" + name + "'"), std::string::npos) << output.substr(0, 500);
    EXPECT_LT(output.size(), 4000u) << "a long value must not be echoed whole";
  }
  std::printf("[measured] start parameters: %d refused by name, %d ran\n", refused, ran);
}

}  // namespace
}  // namespace cloth_sim::test

int main(int argc, char** argv) {
  return cloth_sim::test::runRosTests(argc, argv, "node_bad_input_random_test");
}
