// Small fixtures shared by the core tests.
#pragma once

#include <string>

#include <Eigen/Dense>
#include <Eigen/SparseCore>

#include "cloth_sim/core/linalg/cholmod_factor.h"
#include "cloth_sim/core/model/grid_builder.h"
#include "cloth_sim/core/simulation/simulation.h"
#include "cloth_sim/core/solvers/solver.h"

namespace cloth_sim::test {

/// Path of a file in the source tree (e.g. "config/scenes/hanging.yaml").
std::string sourcePath(const std::string& relative);

/// Two particles joined by one spring along -z, the top one hard-pinned:
/// particle 0 at (0,0,0) pinned, particle 1 at (0,0,-rest) with mass @p mass; stepped by h.
struct HangingSpring {
  Model model;
  Points rest;
  PinSet pins;
  double h = 0.0;  ///< s, the step to solve with (SolverInput::h)
};
HangingSpring makeHangingSpring(double mass, double stiffness, double rest, double h);

/// A small cloth grid (rows x cols, 1 m x 1 m, horizontal at z = 1) with the given stiffnesses.
BuiltObject makeGrid(int rows, int cols, double structural, double shear, double bending);

/// Lets a mass of 0.2 kg hang from a hard-pinned spring (k = 50 N/m, damping 5/s) for 20 s with
/// @p solver and returns the relative error of its stretch against m g / k.
double staticStretchError(Solver& solver, const SolverSettings& settings);

/// Lets a 0.4 kg particle hang from a soft pin (k_pin = 80 N/m, damping 5/s) for 20 s with
/// @p solver and returns the relative error of its sag against m g / k_pin.
double softPinSagError(Solver& solver, const SolverSettings& settings);

/// Steps a free 5 x 5 cloth (no gravity, pins or damping, random velocities) @p steps times
/// (h = 1/60 s) and
/// returns |P_end - P_0| / sum_i m_i |v_i|: the relative drift of the total linear momentum.
double momentumDrift(Solver& solver, const SolverSettings& settings, int steps);

/// M + h^2 L_scalar of a rows x cols grid (makeGrid stiffnesses 400/40/4, no pins): the global
/// step matrix of local/global, symmetric positive definite, both triangles stored.
Eigen::SparseMatrix<double> gridSystemMatrix(int rows, int cols, double h);

/// L of @p factor as a dense matrix (diagonal included).
Eigen::MatrixXd denseLower(const LowerFactor& factor);

/// The peers' cloth at 8 x 8 (1 m, 1 kg, triangle edges at 1000 N/m, two top corners pinned,
/// undamped, released flat) with local_global and @p integrator at 16 substeps of
/// @p iterations per 1/60 s frame (peer_cloth's configuration at 1 iteration).
Simulation makePeerCloth8(Integrator integrator, int iterations);

/// Settings that run an iterative solver to convergence.
SolverSettings convergedSettings(int max_iterations = 100000, double tolerance = 1e-13);

}  // namespace cloth_sim::test
