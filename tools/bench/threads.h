// How the kernels of a frame scale with threads: ms per kernel and per frame at each thread
// count and grid size (docs/benchmark.md, "Threads").
#pragma once

#include <string>
#include <vector>

namespace cloth_sim::bench {

struct ThreadsOptions {
  std::string scenes_dir;  ///< config/scenes
  std::string out_dir;     ///< writes threads.csv there
  std::vector<int> grids{32, 64, 128, 256};
  std::vector<int> threads{1, 2};
  /// The configuration timed: hanging at each grid, one BDF2 step per frame of this solver
  /// with this many iterations (the 128 x 128 bar's configuration by default).
  std::string solver = "anderson";
  int iterations = 10;
  std::string linear_solver = "fused";
  int repeats = 40;        ///< timed calls per kernel and thread count (interleaved)
  int frames = 30;         ///< timed frames per thread count (interleaved)
};

/// For each grid: runs hanging 0.25 s to a moving state, then times, at every thread count,
/// interleaved so that the machine's load falls on all alike: each kernel alone (the local
/// step, the forward and backward solves, one whole local/global iteration, the objective, the
/// acceleration's update, the step's setup) on that state, and whole frames. Writes
/// threads.csv (grid, particles, kernel, threads, median and minimum ms; the minimum is the
/// run least disturbed by other jobs) and prints the speed-up of each kernel.
void runThreads(const ThreadsOptions& options);

}  // namespace cloth_sim::bench
