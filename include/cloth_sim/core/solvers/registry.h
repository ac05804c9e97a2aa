/// @file registry.h
/// The solvers selectable by name: the only list of solvers. Each entry carries what the rest of
/// the code may know of its solver: its name and doc line, its capabilities and its own
/// settings (its block). makeSolver, solverNames, the scene reader (solver.name and the
/// solver.<name>.<field> blocks), the node's ~solver, the runner's --solver and the benchmark's
/// lists follow it; cfg/ClothSim.cfg reads its solver enum from registry.yaml next to
/// registry.cpp, which test/core/solvers/registry_test.cpp compares with this registry.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "cloth_sim/core/solvers/solver.h"

namespace cloth_sim {

/// What a solver honours of SolverSettings and SolverInput (checked against what its step does
/// by test/core/solvers/registry_test.cpp).
struct SolverCapabilities {
  /// The integrators step() discretises with (SolverSettings::integrator). A solver with an
  /// explicit scheme of its own (explicit_euler, verlet, xpbd) lists kImplicitEuler only: the
  /// default setting, meaning "the solver's own scheme".
  std::vector<Integrator> integrators;
  /// Solves SolverInput::contacts with the step (SolveResult::used_contacts when given some);
  /// the others leave contacts to Simulation's projection after the step.
  bool contacts_in_step = false;
  /// SolverSettings::warm_start changes where its iterations start.
  bool warm_start = false;
  /// SolverSettings::max_iterations sets its iterations (a cap for newton).
  bool iterations = false;
  /// SolverSettings::tolerance stops its iterations early.
  bool tolerance = false;

  /// Whether @p integrator is one of integrators.
  bool supports(Integrator integrator) const;
};

/// One selectable solver.
struct SolverEntry {
  const char* name;         ///< what Solver::name() returns and scenes/parameters use
  const char* description;  ///< one line for users (dynamic_reconfigure, --help)
  std::unique_ptr<Solver> (*make)();
  SolverCapabilities capabilities;
  /// Its own settings, the scene's solver.<name>.<field> (SolverParam::field()), read by the
  /// solver from SolverSettings::params; empty for most.
  std::vector<const SolverParam*> params = {};
};

/// Every solver, in the order users see them (explicit baselines first, then the implicit ones).
const std::vector<SolverEntry>& solverRegistry();
/// The names of the solvers whose capabilities have @p capability (e.g.
/// &SolverCapabilities::warm_start), in registry order.
std::vector<std::string> solverNamesWith(bool SolverCapabilities::*capability);
/// The entry called @p name, or nullptr.
const SolverEntry* findSolver(const std::string& name);
/// The entry called @p name; throws std::invalid_argument listing the names if there is none.
const SolverEntry& solverEntry(const std::string& name);

}  // namespace cloth_sim
