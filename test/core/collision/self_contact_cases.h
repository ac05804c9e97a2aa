/// @file self_contact_cases.h
/// Scenes of a cloth in contact with itself at a real thickness, shared by the tests
/// (self_contact_thin_scenes_test.cpp: the strip and bag, a coarse randomized set) and
/// the benchmark (tools/bench/self_collision_set.cpp: the same set up to 128 x 128). Each case
/// is a scene in YAML, as a user would write it, and what moves its pins frame by frame.
/// Header-only, so that the benchmark compiles it without the tests' library.
#pragma once

#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "cloth_sim/core/simulation/simulation.h"

namespace cloth_sim::cases {

/// What a case does with its pins.
enum class Motion {
  kDrop,  ///< nothing: the cloth falls from where it is
  kBag,   ///< the four corner pins gathered above the centre (a bag), kept there
  kFold,  ///< the corner pin carried over the cloth to another corner, then let go
};

struct Case {
  std::string name;  ///< "strip", "sheet", "bag" or "fold"
  unsigned seed = 0;
  std::string yaml;
  double thickness = 0.0;  ///< m
  int resolution = 0;      ///< particles along the longer side
  int frames = 0;          ///< at 60 Hz
  Motion motion = Motion::kDrop;
  double move_time = 0.0;  ///< s: the bag's gathering, the fold's carry
  double lift = 0.0;       ///< m: the fold's arc
  bool side_fold = false;  ///< fold onto the next corner (in half) instead of the opposite one
};

/// The scene's shared part: 1/60 s frames, 8 substeps of 2 iterations, the ground.
inline std::string header(double structural) {
  std::ostringstream y;
  y << "time_step: 1/60\nsolver: {name: local_global, iterations: 2, substeps: 8}\n"
    << "material:\n  areal_density: 0.2\n  damping: 0.1\n  springs: {structural: " << structural
    << ", shear: " << structural / 10 << ", bending: " << structural / 100 << "}\n"
    << "colliders:\n  ground: {height: 0.0, friction: 0.5}\n";
  return y.str();
}

/// @p c with no solver block: the scene format's default then, error control (the substeps of
/// each frame chosen by the local error estimate, BDF2; docs/method.md, "Error control").
inline Case underErrorControl(Case c) {
  const std::string block = "solver: {name: local_global, iterations: 2, substeps: 8}\n";
  const std::size_t at = c.yaml.find(block);
  if (at != std::string::npos) c.yaml.erase(at, block.size());
  c.name += " (error control)";
  return c;
}

/// The strip: 0.2 x 1.6 m, 10 x 64 particles (spacing 22 and 25 mm), 300 N/m, dropped
/// upright (leaning 7 degrees) onto the ground, 2 s.
inline Case strip(double thickness) {
  Case c;
  c.name = "strip";
  c.thickness = thickness;
  c.resolution = 64;
  c.frames = 120;
  std::ostringstream y;
  y << header(300) << "cloth:\n  grid: {rows: 64, cols: 10, size: [0.2, 1.6], position: [0, 0, "
    << "0.85], orientation_rpy: [1.45, 0, 0]}\nself_collision: {thickness: " << thickness
    << ", friction: 0.3}\n";
  c.yaml = y.str();
  return c;
}

/// The bag: a 0.9 m sheet of 30 x 30 (spacing 31 mm) lying 0.3 m up, its four corners
/// gathered in 2 s to a 4 cm square 0.5 m above its centre, 3 s.
inline Case bag(double thickness) {
  Case c;
  c.name = "bag";
  c.thickness = thickness;
  c.resolution = 30;
  c.frames = 180;
  c.motion = Motion::kBag;
  c.move_time = 2.0;
  std::ostringstream y;
  y << header(400) << "cloth:\n  grid: {rows: 30, cols: 30, size: [0.9, 0.9], position: [0, 0, "
    << "0.3]}\npins:\n  - {row: 0, col: 0}\n  - {row: 0, col: 29}\n  - {row: 29, col: 0}\n"
    << "  - {row: 29, col: 29}\nself_collision: {thickness: " << thickness
    << ", friction: 0.3}\n";
  c.yaml = y.str();
  return c;
}

/// A random case of seed @p seed: a strip or a square sheet dropped upright, a bag or a fold;
/// thickness 1 to 10 mm; @p min_res to @p max_res particles along the longer side; @p seconds
/// of simulated time.
inline Case random(unsigned seed, int min_res, int max_res, double seconds) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Case c;
  c.seed = seed;
  static const char* kNames[] = {"strip", "sheet", "bag", "fold"};
  const int kind = static_cast<int>(seed % 4);
  c.name = kNames[kind];
  c.thickness = 0.001 * std::round(1.0 + 9.0 * u(rng));  // 1 to 10 mm
  c.resolution = min_res + static_cast<int>(std::floor(u(rng) * (max_res - min_res + 1)));
  c.frames = static_cast<int>(std::lround(60.0 * seconds));
  const int n = c.resolution;
  std::ostringstream y;
  y << header(100 + 400 * u(rng));
  if (kind <= 1) {  // strip or sheet, upright
    const double length = 0.8 + 0.8 * u(rng);
    const double width = kind == 0 ? length * (0.12 + 0.15 * u(rng)) : length;
    const int cols = kind == 0 ? std::max(4, static_cast<int>(std::lround(n * width / length))) : n;
    const double lean = 0.05 + 0.2 * u(rng), yaw = 6.0 * u(rng), drop = 0.02 + 0.2 * u(rng);
    y << "cloth:\n  grid: {rows: " << n << ", cols: " << cols << ", size: [" << width << ", "
      << length << "], position: [0, 0, " << drop + 0.5 * length * std::cos(lean)
      << "], orientation_rpy: [" << M_PI / 2 - lean << ", 0, " << yaw << "]}\n";
  } else {
    const double size = 0.6 + 0.6 * u(rng);
    y << "cloth:\n  grid: {rows: " << n << ", cols: " << n << ", size: [" << size << ", " << size
      << "], position: [0, 0, " << (kind == 2 ? 0.3 : 0.0) << "]}\n";
    if (kind == 2) {
      y << "pins:\n  - {row: 0, col: 0}\n  - {row: 0, col: " << n - 1 << "}\n  - {row: " << n - 1
        << ", col: 0}\n  - {row: " << n - 1 << ", col: " << n - 1 << "}\n";
      c.motion = Motion::kBag;
      c.move_time = 1.0 + u(rng);
    } else {
      y << "pins:\n  - {row: 0, col: 0}\n";
      c.motion = Motion::kFold;
      c.move_time = 0.8 + 0.8 * u(rng);
      c.lift = (0.2 + 0.3 * u(rng)) * size;
      c.side_fold = u(rng) < 0.5;
    }
  }
  y << "self_collision: {thickness: " << c.thickness << ", friction: " << 0.5 * u(rng) << "}\n";
  c.yaml = y.str();
  return c;
}

/// Moves @p c's pins before frame @p frame (1-based) of @p sim; @p start holds each pin's
/// target at the start (filled at frame 1).
inline void beforeFrame(const Case& c, Simulation& sim, int frame, std::vector<Vec3>& start) {
  if (c.motion == Motion::kDrop) return;
  const std::vector<Pin>& pins = sim.pins().pins();
  if (frame == 1) {
    start.clear();
    for (const Pin& p : pins) start.push_back(p.target);
  }
  const double time = frame * sim.frameTime();
  const double s = std::min(1.0, time / c.move_time);
  const double along = 0.5 * (1.0 - std::cos(M_PI * s));
  if (c.motion == Motion::kBag) {
    Vec3 centre = Vec3::Zero();
    for (const Vec3& p : start) centre += p / static_cast<double>(start.size());
    for (std::size_t k = 0; k < pins.size() && k < start.size(); ++k) {
      const Vec3 off = start[k] - centre;
      const Vec3 to = centre + Vec3(0, 0, 0.5) + 0.02 * Vec3(off.x() > 0 ? 1 : -1, off.y() > 0 ? 1 : -1, 0);
      sim.movePin(pins[k].id, start[k] + along * (to - start[k]));
    }
    return;
  }
  // Fold: over an arc onto the opposite corner (or the next one), one thickness up; let go.
  if (pins.empty()) return;
  const int n = static_cast<int>(std::lround(std::sqrt(sim.model().particleCount())));
  const int to_vertex = c.side_fold ? n * (n - 1) : n * n - 1;
  if (time > c.move_time + 0.5 * sim.frameTime()) {
    sim.removePin(pins.front().id);
    return;
  }
  const Vec3 to = sim.initialPositions().col(to_vertex) + Vec3(0, 0, c.thickness);
  sim.movePin(pins.front().id, start[0] + along * (to - start[0]) +
                                   Vec3(0, 0, c.lift * std::sin(M_PI * s)));
}

}  // namespace cloth_sim::cases
