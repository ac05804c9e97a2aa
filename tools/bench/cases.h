// The benchmark's scenes: the shipped hanging and drape scenes resized, and Liu et al.'s cloth.
#pragma once

#include <string>
#include <vector>

#include "cloth_sim/core/io/scene.h"

namespace cloth_sim::bench {

/// One scene at one resolution.
struct BenchCase {
  std::string name;    ///< e.g. "hanging-64", "paper-81"
  std::string scene;   ///< "hanging" or "drape"
  int grid = 0;        ///< rows = cols
  bool paper = false;  ///< Liu et al. 2013 topology: triangle diagonals + bending, h = 1/30 s
  SceneConfig config;  ///< the scene file with the grid (and topology) replaced
};

/// @p config with every solver field it leaves to the defaults fixed as it now stands (its
/// substeps, iterations and integrator, no error tolerance): the benchmark sweeps fixed
/// configurations, not the error-controlled default (resolveSolverDefaults), unless a
/// configuration asks for it.
SceneConfig fixedConfiguration(SceneConfig config);

/// Loads config/scenes/<scene>.yaml from @p scenes_dir and sets a grid x grid cloth of the same
/// size and material (stiffness per spring is resolution independent in 2D; the particles get
/// lighter, so the problem gets stiffer relative to mass, as it does for a user who refines).
BenchCase makeCase(const std::string& scenes_dir, const std::string& scene, int grid);

/// The paper's 81 x 81 cloth (6,561 particles, 32,158 springs): the hanging scene with only the
/// triangulation diagonals as shear springs, distance-2 bending springs and h = 1/30 s.
BenchCase makePaperCase(const std::string& scenes_dir);

/// The same configuration with another solver, iteration count, linear solver and warm start.
SceneConfig withSolver(SceneConfig config, const std::string& solver, int iterations,
                       LinearSolver linear, bool warm_start = false);

}  // namespace cloth_sim::bench
