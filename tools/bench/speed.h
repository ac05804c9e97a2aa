// Speed against error: every solver and iteration count on the benchmark scenes (docs/benchmark.md).
#pragma once

#include <string>
#include <vector>

namespace cloth_sim::bench {

struct SpeedOptions {
  std::string scenes_dir;                         ///< config/scenes
  std::string out_dir;                            ///< CSV files go here
  std::string cache_dir;                          ///< Newton references; empty = no cache
  std::vector<std::string> scenes = {"hanging", "drape"};
  std::vector<int> grids = {32, 64, 81, 128};
  bool paper = true;                              ///< also the paper's 81 x 81 cloth
  std::vector<std::string> solvers;               ///< labels (solverLabels()); empty = all
  std::vector<int> iterations = {1, 2, 5, 10, 20, 50};
  double duration = 1.0;   ///< s of simulated time per timed run (from rest)
  int samples = 4;         ///< states along the trajectory where the error is measured
  double budget = 6.0;     ///< s of wall time after which a timed run stops (>= min_steps)
  int min_steps = 4;
  /// cap of the per-iteration error traces (the local/global family: those with an iterate
  /// observer)
  int trace_iterations = 3000;
};

/// The solver configurations the benchmark knows, from the solver registry: every solver by
/// name (the default one, local_global, with the fused kernels), the default solver with each
/// other linear solver ("local_global:cholmod", "local_global:eigen"), and "<solver>+warm" for
/// each solver whose capabilities have warm_start (SolverSettings::warm_start). "@p" after a
/// label sets the first setting of the solver's own (its entry's params: chebyshev's rho,
/// anderson's or lbfgs's window).
std::vector<std::string> solverLabels();

/// Runs the benchmark and writes speed.csv, traces.csv, references.csv and cases.csv.
void runSpeed(const SpeedOptions& options);

}  // namespace cloth_sim::bench
