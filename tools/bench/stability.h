// Stability sweep: every solver over stiffness, time step and three hard cases (docs/benchmark.md).
#pragma once

#include <string>
#include <vector>

#include "cloth_sim/core/io/scene.h"

namespace cloth_sim::bench {

/// The hard cases of the sweep, all on the same curtain: a 1 m x 1 m cloth, 0.2 kg/m^2,
/// structural k, shear k/10, bending k/100 N/m, hard-pinned along its top edge.
enum class Scenario {
  kRelease,   ///< held horizontal, released: swings down like a flap around its top edge
  kTeleport,  ///< hanging at rest; at t = 0.5 s its pins (the top edge) jump 1 m sideways
  kSphere,    ///< hanging at rest; at t = 0.5 s a kinematic sphere (r = 0.1 m) crosses its
              ///< lower part at 20 m/s, perpendicular to it, and flies on
};
const char* scenarioName(Scenario s);

/// The sweep's solvers by default, from the solver registry: every solver, and the default
/// solver (SimulationOptions::solver) with each other integrator ("local_global/bdf2").
std::vector<std::string> defaultStabilitySolvers();
/// What the sweep accepts: every solver, and "<solver>/<integrator>" for each other integrator
/// its registry entry supports.
std::vector<std::string> stabilitySolverChoices();

struct StabilityOptions {
  std::string out_dir;
  int grid = 16;                     ///< particles per side
  std::vector<double> stiffness = {1e1, 1e2, 1e3, 1e4, 1e5, 1e6};  ///< structural, N/m
  std::vector<double> time_steps = {1.0 / 240, 1.0 / 120, 1.0 / 60, 1.0 / 30, 1.0 / 15};
  /// A solver name, or "<solver>/<integrator>" for another SolverSettings::integrator.
  std::vector<std::string> solvers = defaultStabilitySolvers();
  std::vector<Scenario> scenarios = {Scenario::kRelease, Scenario::kTeleport, Scenario::kSphere};
  int iterations = 10;               ///< per step (newton: cap)
  /// s: the event is at 0.5 s; 2.5 s later even the 10 N/m cloth has settled under 100 %.
  double duration = 3.0;
  /// 1/s, Model::damping. 0.5 as in the trampoline scene: air drag on a 0.2 kg/m^2 cloth moving
  /// at 1 m/s is of that order or more (0.5 rho_air C_d v^2 / (0.2 kg/m^2) v = 1-3 /s).
  double damping = 0.5;
};

/// What one cell did.
struct CellResult {
  Scenario scenario = Scenario::kRelease;
  std::string solver;
  double stiffness = 0.0, time_step = 0.0;
  int steps = 0, rollbacks = 0;      ///< steps rolled back by Simulation (non-finite/diverged)
  bool finite = true;
  double peak_strain = 0.0;          ///< max over the run
  double end_strain = 0.0;           ///< max over the last 0.25 s
  double peak_energy = 0.0, end_energy = 0.0;  ///< J
  /// stable: finite, never rolled back, and back under 100 % strain by the end; a transient
  /// over 100 % (peak_strain) is reported apart, see docs/benchmark.md, "Stability".
  bool stable() const { return finite && rollbacks == 0 && end_strain <= 1.0; }
};

/// The scene of one cell (the sphere and the teleport are applied by runCell). @p solver: a
/// solver name or "<solver>/<integrator>" ("local_global/bdf2").
SceneConfig stabilityScene(Scenario scenario, int grid, double stiffness, double time_step,
                           const std::string& solver, int iterations, double damping);

/// Runs one cell.
CellResult runCell(Scenario scenario, int grid, double stiffness, double time_step,
                   const std::string& solver, int iterations, double duration, double damping);

/// Runs every cell and writes stability.csv to out_dir.
void runStability(const StabilityOptions& options);

}  // namespace cloth_sim::bench
