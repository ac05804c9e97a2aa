// Small fixtures shared by the core tests.
#pragma once

#include <string>

#include "cloth_sim/core/grid_builder.h"
#include "cloth_sim/core/simulation.h"

namespace cloth_sim::test {

/// Path of a file in the source tree (e.g. "config/scenes/hanging.yaml").
std::string sourcePath(const std::string& relative);

/// Two particles joined by one spring along -z, the top one hard-pinned:
/// particle 0 at (0,0,0) pinned, particle 1 at (0,0,-rest) with mass @p mass.
struct HangingSpring {
  Model model;
  Points rest;
  PinSet pins;
};
HangingSpring makeHangingSpring(double mass, double stiffness, double rest, double h);

/// A small cloth grid (rows x cols, 1 m x 1 m, horizontal at z = 1) with the given stiffnesses.
BuiltObject makeGrid(int rows, int cols, double structural, double shear, double bending);

/// Settings that run an iterative solver to convergence.
SolverSettings convergedSettings(int max_iterations = 100000, double tolerance = 1e-13);

}  // namespace cloth_sim::test
