// Randomized live settings on a real master (issue 23): dynamic_reconfigure driven with random
// values, each range's ends among them (the sliders: 100,000 iterations, 1,000 substeps, 1e5 N/m,
// explicit solvers, budgets beyond the frame), random pin targets (some beyond the cloth's reach)
// and random spheres (some too large or too fast), for 60 s of simulated time. Asserts that every
// call, and a cloth/step report between the inputs, answers within 1 s (iterations, substeps
// and self-collision are put back after their input's 0.5 s, as a user tries a slider); that no input's cause
// resets the cloth more than once (a reset that would repeat is held instead); and that every
// state is finite. The seed is fixed and printed (CLOTH_SIM_RANDOM_SEED runs another).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <mutex>
#include <random>

#include <dynamic_reconfigure/Reconfigure.h>
#include <gtest/gtest.h>

#include <cloth_sim/PinMove.h>
#include <cloth_sim/RemoveSphere.h>
#include <cloth_sim/SpawnSphere.h>
#include <cloth_sim/Step.h>

#include "ros_test_util.h"

namespace cloth_sim::test {
namespace {

constexpr double kSimulated = 60.0;     // s of simulated time
constexpr double kPerInput = 0.5;       // s of simulated time between two inputs
constexpr double kMaxLatency = 1.0;     // s, every answer
constexpr double kWallLimit = 420.0;    // s, the test gives up (and fails) after this

/// What the node's states say, watched on a subscriber of its own.
struct Watch {
  std::mutex mutex;
  double simulated = 0.0;  ///< s, summed over resets
  double last_sim_time = 0.0;
  std::uint32_t resets = 0;
  int states = 0, non_finite = 0, held = 0;
  std::string last_notice;

  void onState(const ClothState& s) {
    std::lock_guard<std::mutex> lock(mutex);
    simulated += s.sim_time >= last_sim_time ? s.sim_time - last_sim_time : s.sim_time;
    last_sim_time = s.sim_time;
    resets = std::max(resets, s.divergence_resets);
    ++states;
    if (!std::isfinite(s.energy) || !std::isfinite(s.max_strain)) ++non_finite;
    if (s.notice.find("held:") != std::string::npos && s.notice != last_notice) ++held;
    last_notice = s.notice;
  }
};

double since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// An integer in [lo, hi]: an end with probability 0.2 each, else log-uniform.
long pickInt(std::mt19937& rng, long lo, long hi) {
  const double u = std::uniform_real_distribution<double>(0, 1)(rng);
  if (u < 0.2) return lo;
  if (u < 0.4) return hi;
  const double a = std::log(std::max(1L, lo)), b = std::log(double(hi));
  return std::clamp(long(std::lround(std::exp(std::uniform_real_distribution<double>(a, b)(rng)))),
                    lo, hi);
}

/// A number in [lo, hi]: an end with probability 0.2 each, else log-uniform above hi / 1e4.
double pickDouble(std::mt19937& rng, double lo, double hi) {
  const double u = std::uniform_real_distribution<double>(0, 1)(rng);
  if (u < 0.2) return lo;
  if (u < 0.4) return hi;
  const double a = std::log(hi * 1e-4), b = std::log(hi);
  return std::clamp(std::exp(std::uniform_real_distribution<double>(a, b)(rng)), lo, hi);
}

TEST(ReconfigureRandom, AnswersWithinASecondAndNoCauseResetsTwice) {
  unsigned seed = 20260323;
  if (const char* s = std::getenv("CLOTH_SIM_RANDOM_SEED")) seed = unsigned(std::atol(s));
  std::printf("[measured] reconfigure_random: seed %u\n", seed);
  std::mt19937 rng(seed);
  ros::NodeHandle nh;
  Watch watch;
  ros::Subscriber sub = nh.subscribe<ClothState>(
      names::kState, 50, [&](const ClothState::ConstPtr& s) { watch.onState(*s); });
  ros::Publisher pin_pub = nh.advertise<PinMove>(names::kPinMove, 10);
  NodeProbe probe{nh};
  ASSERT_TRUE(probe.waitForTraffic(60.0));
  ASSERT_TRUE(waitForSubscriber(pin_pub));
  const ClothState first = probe.latestState();
  const Vec3 centre(0.0, 0.0, 1.0);  // sag.yaml's sheet, 0.5 m

  double worst_latency = 0.0;
  int inputs = 0, reconfigures = 0, refused_fields = 0, pin_moves = 0, spheres = 0,
      spheres_refused = 0, double_resets = 0, probes = 0;
  std::vector<int> sphere_ids;
  auto timed = [&](auto&& call_it) {
    const auto t0 = std::chrono::steady_clock::now();
    call_it();
    const double took = since(t0);
    worst_latency = std::max(worst_latency, took);
    EXPECT_LT(took, kMaxLatency) << "input " << inputs;
  };
  const auto wall0 = std::chrono::steady_clock::now();
  while (since(wall0) < kWallLimit) {
    double simulated;
    std::uint32_t resets_before;
    {
      std::lock_guard<std::mutex> lock(watch.mutex);
      simulated = watch.simulated;
      resets_before = watch.resets;
    }
    if (simulated >= kSimulated) break;
    ++inputs;
    dynamic_reconfigure::Reconfigure::Request put_back;
    const int kind = std::uniform_int_distribution<int>(0, 9)(rng);
    if (kind < 6) {  // dynamic_reconfigure, one random field
      dynamic_reconfigure::Reconfigure::Request req;
      const int field = std::uniform_int_distribution<int>(0, 10)(rng);
      auto dbl = [&](const char* name, double v) {
        dynamic_reconfigure::DoubleParameter p;
        p.name = name;
        p.value = v;
        req.config.doubles.push_back(p);
      };
      auto integer = [&](const char* name, int v) {
        dynamic_reconfigure::IntParameter p;
        p.name = name;
        p.value = v;
        req.config.ints.push_back(p);
      };
      auto str = [&](const char* name, const std::string& v) {
        dynamic_reconfigure::StrParameter p;
        p.name = name;
        p.value = v;
        req.config.strs.push_back(p);
      };
      const char* solvers[] = {"explicit_euler", "verlet", "newton", "local_global", "chebyshev",
                               "anderson", "lbfgs", "local_global_3n", "xpbd"};
      switch (field) {
        case 0: dbl("structural_stiffness", pickDouble(rng, 0, 1e5)); break;
        case 1: dbl("shear_stiffness", pickDouble(rng, 0, 1e5)); break;
        case 2: dbl("bending_stiffness", pickDouble(rng, 0, 1e5)); break;
        case 3: dbl("damping", pickDouble(rng, 0, 100)); break;
        case 4: str("solver", solvers[std::uniform_int_distribution<int>(0, 8)(rng)]); break;
        case 5: integer("iterations", int(pickInt(rng, 1, 100000))); break;
        case 6: integer("substeps", int(pickInt(rng, 0, 1000))); break;
        case 7: dbl("error_tolerance", pickDouble(rng, 0, 0.01)); break;
        case 8: dbl("budget_ms", pickDouble(rng, 0, 100)); break;
        case 9: {
          dynamic_reconfigure::BoolParameter p;
          p.name = "self_collision";
          p.value = std::uniform_int_distribution<int>(0, 1)(rng) == 1;
          req.config.bools.push_back(p);
          break;
        }
        default: str("color_mode", std::uniform_int_distribution<int>(0, 1)(rng) ? "strain" : "shaded");
      }
      // The value in use before, put back after the input's time (as a user tries a slider and
      // lets go), so that one heavy setting does not hold the rest of the run.
      const dynamic_reconfigure::Config before =
          call<dynamic_reconfigure::Reconfigure>(names::setParameters(), {}).config;
      put_back = dynamic_reconfigure::Reconfigure::Request();
      auto restore = [&](const auto& requested, const auto& in_use, auto& out) {
        for (const auto& r : requested) {
          for (const auto& b : in_use) {
            if (b.name == r.name) out.push_back(b);
          }
        }
      };
      // Only the costly ones: stiffnesses and solvers stay, so that an explicit solver meets a
      // stiff cloth, diverges and is reset (then held).
      restore(req.config.ints, before.ints, put_back.config.ints);  // iterations, substeps
      restore(req.config.bools, before.bools, put_back.config.bools);  // self_collision
      timed([&] {
        const auto res = call<dynamic_reconfigure::Reconfigure>(names::setParameters(), req);
        // A refused value comes back as the one in use.
        for (const auto& d : req.config.doubles) {
          for (const auto& r : res.config.doubles) {
            if (r.name == d.name && r.value != d.value) ++refused_fields;
          }
        }
        for (const auto& i : req.config.ints) {
          for (const auto& r : res.config.ints) {
            if (r.name == i.name && r.value != i.value) ++refused_fields;
          }
        }
      });
      ++reconfigures;
    } else if (kind < 8) {  // a pin target, up to 1.5 m away (the reach is 0.75 m)
      const ClothState s = probe.latestState();
      if (!s.pins.empty()) {
        const PinInfo& pin = s.pins[std::uniform_int_distribution<std::size_t>(0, s.pins.size() - 1)(rng)];
        std::uniform_real_distribution<double> off(-1.5, 1.5);
        PinMove move;
        move.id = pin.id;
        move.target = stamped("world", first.pins.front().target.x + off(rng),
                              first.pins.front().target.y + off(rng),
                              first.pins.front().target.z + off(rng));
        pin_pub.publish(move);
        ++pin_moves;
      }
    } else if (kind < 9 || sphere_ids.empty()) {  // a sphere, up to too large and too fast
      SpawnSphere::Request req;
      std::uniform_real_distribution<double> off(-0.7, 0.7), speed(-4.0, 4.0);
      req.center = stamped("world", centre.x() + off(rng), centre.y() + off(rng),
                           centre.z() + off(rng));
      req.radius = pickDouble(rng, 0.005, 0.6);
      req.velocity.x = speed(rng);
      req.velocity.y = speed(rng);
      req.velocity.z = speed(rng);
      req.mass = std::uniform_int_distribution<int>(0, 1)(rng) ? 0.0 : pickDouble(rng, 1e-3, 10.0);
      timed([&] {
        const auto res = call<SpawnSphere>(names::kSpawnSphere, req);
        if (res.success) {
          sphere_ids.push_back(res.id);
          ++spheres;
        } else {
          ++spheres_refused;
        }
      });
    } else {  // remove one (it may have been culled: then refused)
      RemoveSphere::Request req;
      req.id = sphere_ids.back();
      sphere_ids.pop_back();
      timed([&] { call<RemoveSphere>(names::kRemoveSphere, req); });
    }
    // Until kPerInput s more are simulated: a report at once and every 0.2 s after must answer
    // within 1 s.
    auto last_probe = std::chrono::steady_clock::time_point();
    while (since(wall0) < kWallLimit) {
      if (last_probe == std::chrono::steady_clock::time_point() || since(last_probe) > 0.2) {
        timed([&] {
          Step::Request report;
          report.frames = 0;
          EXPECT_TRUE(call<Step>(names::kStep, report).success);
        });
        last_probe = std::chrono::steady_clock::now();
        ++probes;
      }
      {
        std::lock_guard<std::mutex> lock(watch.mutex);
        if (watch.simulated >= simulated + kPerInput) break;
      }
      ros::WallDuration(0.002).sleep();
    }
    {
      std::lock_guard<std::mutex> lock(watch.mutex);
      if (watch.resets > resets_before + 1) ++double_resets;
    }
    if (!put_back.config.doubles.empty() || !put_back.config.ints.empty() ||
        !put_back.config.strs.empty() || !put_back.config.bools.empty()) {
      timed([&] { call<dynamic_reconfigure::Reconfigure>(names::setParameters(), put_back); });
    }
  }
  const double wall = since(wall0);
  std::lock_guard<std::mutex> lock(watch.mutex);
  std::printf("[measured] reconfigure_random: %d inputs (%d reconfigure, %d fields refused; %d pin "
              "moves; %d spheres, %d refused) over %.1f s simulated in %.1f s wall; slowest answer "
              "%.3f s (%d reports); %u automatic resets, %d holds, %d states\n",
              inputs, reconfigures, refused_fields, pin_moves, spheres, spheres_refused,
              watch.simulated, wall, worst_latency, probes, watch.resets, watch.held, watch.states);
  EXPECT_GE(watch.simulated, kSimulated) << "did not simulate 60 s within " << kWallLimit << " s";
  EXPECT_LT(worst_latency, kMaxLatency);
  EXPECT_EQ(double_resets, 0) << "an input's cause reset the cloth more than once";
  EXPECT_EQ(watch.non_finite, 0);
}

}  // namespace
}  // namespace cloth_sim::test

int main(int argc, char** argv) {
  return cloth_sim::test::runRosTests(argc, argv, "node_reconfigure_random_test");
}
