// The single-precision factor against the double one: speed of the solves and of an iteration,
// and the fixed point reached (docs/benchmark.md, "Threads", "The single-precision factor").
#pragma once

#include <string>
#include <vector>

namespace cloth_sim::bench {

struct PrecisionOptions {
  std::string scenes_dir;  ///< config/scenes
  std::string out_dir;     ///< writes precision.csv there
  std::vector<int> grids{32, 64, 128, 256};
  std::vector<int> threads{1, 2};
  int repeats = 30;        ///< timed calls per kernel, backend and thread count (interleaved)
  int frames = 60;         ///< frames of the trajectories compared (1 s at 60 Hz)
};

/// For each grid (hanging, one BDF2 step per frame of anderson, as `threads`): times the fused
/// solve (forward + backward) and one local/global iteration with the double factor and the
/// float one at each thread count, interleaved; then compares the two backends' results: after
/// one frame converged to a relative change of 1e-13 (the fixed point), after one frame of 10
/// iterations, and after @c frames frames of 10 iterations (as RMS and max distance, as a
/// fraction of the cloth's diagonal), the last beside the distance between two double backends
/// that differ in round-off only (fused and CHOLMOD's solve). Writes precision.csv (grid, particles, quantity, threads,
/// value) and prints a summary.
void runPrecision(const PrecisionOptions& options);

}  // namespace cloth_sim::bench
