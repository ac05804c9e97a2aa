// Accuracy against the true motion: every configuration (solver x substeps x iterations) is run
// frame by frame on the shipped scenes and compared, at fixed simulated times, with the same
// scene run at a tiny step to convergence (docs/benchmark.md, "Accuracy against the true motion").
#pragma once

#include <string>
#include <vector>

#include "cloth_sim/core/io/scene.h"
#include "cloth_sim/core/solvers/registry.h"

namespace cloth_sim::bench {

struct AccuracyOptions {
  std::string scenes_dir;  ///< config/scenes
  /// bench/scenes: scenes written as a user would, with no solver block (nobody tuned them);
  /// a scene name is looked up in scenes_dir, then here.
  std::string untuned_dir;
  std::string out_dir;     ///< accuracy.csv, accuracy_reference.csv
  std::string cache_dir;   ///< reference trajectories ('' = recompute every time)
  std::vector<std::string> scenes = {"hanging", "drape", "trampoline", "gravity_well",
                                     "tablecloth", "peer_cloth"};
  /// Particles per side; a mesh scene (tablecloth) runs once at its own resolution.
  std::vector<int> grids = {32, 64, 128};
  /// By default the solvers that solve contacts in the step (their registry entry's
  /// capabilities), the ones meant for scenes in contact such as these.
  std::vector<std::string> solvers = solverNamesWith(&SolverCapabilities::contacts_in_step);
  /// Every configuration (newton's too) runs once per integrator (SolverSettings::integrator);
  /// a bdf2 run is labelled "<solver>/bdf2", an implicit Euler one by the solver's name.
  std::vector<std::string> integrators = {"implicit_euler", "bdf2"};
  std::vector<int> substeps = {1, 2, 4, 8, 16};
  /// Substeps per frame of the solvers without a convergence test (no tolerance in their
  /// capabilities), run the small-steps way (Macklin et al. 2019): xpbd runs these with 1
  /// iteration each, and only with its own scheme (a solver is run only with the integrators
  /// it supports).
  std::vector<int> xpbd_substeps = {4, 8, 16, 32, 64, 128, 256, 512};
  std::vector<int> iterations = {1, 2, 3, 5, 10, 20};
  /// Error-controlled configurations (docs/method.md, "Error control"): each of these solvers
  /// runs once per tolerance (m per frame, substeps chosen by the estimate, at most 100
  /// iterations), with BDF2 and with implicit Euler.
  std::vector<std::string> error_control_solvers = {"local_global"};
  std::vector<double> error_tolerances = {1e-4, 3e-5, 1e-5, 3e-6};
  /// Run the scene format's default too (a scene with no solver block: error control with
  /// BDF2 at kDefaultRelativeErrorTolerance x the cloth's size), labelled "default".
  bool scene_default = true;
  /// The default's integrator instead of the format's ("" = the format's, BDF2): a scene that
  /// gives only solver.integrator, to compare integrators under the default error control.
  std::string default_integrator;
  /// Only the default (no sweep, no Newton rows): the check of the scene format's default.
  bool default_only = false;
  /// Error-controlled configurations: the local error of this many frames, evenly spread up to
  /// local_error_until (s), is measured against the true motion from the same state
  /// (local_error.csv: the estimate against the truth). 0 = none.
  int local_error_frames = 10;
  double local_error_until = 1.0;
  /// The true frame: implicit Euler converged at this many substeps and twice as many,
  /// extrapolated (Richardson).
  int local_error_substeps = 64;
  /// Newton at full convergence (the best a step of that size can do), only up to this grid.
  int newton_max_grid = 32;
  /// Simulated times (s) at which positions, energy, strain and the centre of mass are compared
  /// (0.25 s and 0.5 s: where the peers report; the swing's damping shows later).
  std::vector<double> times = {0.25, 0.5, 1.0, 1.5, 2.0, 3.0};
  /// "verlet": velocity Verlet (second order, no numerical damping, so it does not
  /// favour implicit Euler's damping) at frame / (2 n), n the larger of reference_substeps and
  /// half of Verlet's stability limit; its own error is estimated by its distance to the
  /// same run at frame / n (second order: that distance is about 3x the finer run's error).
  /// "implicit": implicit Euler solved to convergence (chebyshev, relative change 1e-9) at
  /// h = frame / (2 n), n = reference_substeps; its own error is estimated by its distance to
  /// the same run at frame / n (first order: that distance is about the finer run's error).
  /// "bdf2": BDF2 solved to convergence the same way at h = frame / (2 n), n the larger of
  /// reference_substeps and kContactReferenceSubsteps (second order, as verlet).
  /// "auto" (default): verlet for a scene without colliders, bdf2 with them. Implicit Euler's
  /// numerical damping kept too little of the true motion's energy at frame / 64 (trampoline:
  /// 2.2 J at 1 s where BDF2 converges to 7.8 J; table_edge 0.044 J against 0.094 J).
  std::string reference = "auto";
  int reference_substeps = 32;
  /// The least n of a "bdf2" reference: at frame / 512 and / 1024 BDF2's energies at 1 s agree
  /// within 1.1 % on trampoline, ball_drop, curtain and table_edge (32 x 32).
  static constexpr int kContactReferenceSubsteps = 512;
  /// Run the local/global family's configurations warm-started (SolverSettings::warm_start).
  bool warm_start = false;
  /// A configuration whose first frames take more than this (ms per frame) is not run to the
  /// end: it is far off the real-time front and would only cost benchmark time. The scene's
  /// default always runs to the end (the bars judge it).
  double max_frame_ms = 100.0;
};

/// Substeps per frame for velocity Verlet at half its stability limit h < 2 / w_max, rounded up
/// to a power of two (w_max from Gershgorin on M^-1 K at rest): the "verlet" reference's step.
int verletSubsteps(const SceneConfig& scene);

/// The true motion of one case at fixed times, as runAccuracy computes it (and caches it in
/// AccuracyOptions::cache_dir): the reference run at h and at h / 2 (see
/// AccuracyOptions::reference). Other benchmarks (cloth_sim_bench peers) measure against it.
struct TrueMotion {
  std::string kind;                ///< "verlet", "implicit" or "bdf2" (referenceKind)
  double h = 0.0;                  ///< s, the finer run's step
  double diagonal = 0.0;           ///< m, of the cloth's bounding box at rest (the error scale)
  std::vector<int> frames;         ///< the sample frames (times / frame, rounded)
  std::vector<Points> positions;   ///< the finer run (h) at each sample frame: the truth
  std::vector<Points> coarse;      ///< the run at 2 h: its distance to the truth is the floor
  std::vector<double> energy;      ///< J, Simulation::totalEnergy of the finer run
  /// J, the same of the run at 2 h: how far the truth's own energy moves with its step.
  std::vector<double> coarse_energy;
  std::vector<double> mean_strain; ///< mean |l - r| / r over the springs, finer run
  std::vector<double> max_strain;
};

/// The true motion of @p scene (case name @p case_name, the cache's key) at @p times (s).
TrueMotion trueMotion(const SceneConfig& scene, const std::string& case_name,
                      const std::vector<double>& times, const AccuracyOptions& options);

/// Runs the sweep; writes accuracy.csv and accuracy_reference.csv into out_dir and prints a
/// progress bar and one line per configuration.
void runAccuracy(const AccuracyOptions& options);

}  // namespace cloth_sim::bench
