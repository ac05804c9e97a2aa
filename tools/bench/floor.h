// The memory-bandwidth floor of one local/global iteration on the paper's 81 x 81 cloth, and
// the measured per-iteration cost of every global-step implementation (docs/benchmark.md, "Performance").
#pragma once

#include <string>

namespace cloth_sim::bench {

struct FloorOptions {
  std::string scenes_dir, out_dir;
  int steps = 60;      ///< steps per timed run
  int rounds = 5;      ///< runs per configuration, interleaved; medians over all steps
};

/// Writes floor.csv (bytes, bandwidths, floors) and kernels.csv (ms per step and per iteration
/// of local_global with each LinearSolver, of local_global_3n and chebyshev, and of the kernels
/// alone) to out_dir, and prints a summary.
void runFloor(const FloorOptions& options);

}  // namespace cloth_sim::bench
