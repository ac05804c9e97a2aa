/// @file registry.h
/// The solvers selectable by name: the only list of solver names (makeSolver, solverNames, the
/// scene reader, the node's ~solver and reconfigure enum, the runner's --solver all use it;
/// cfg/ClothSim.cfg is compared with it by test/node/reconfigure_cfg_test.cpp).
#pragma once

#include <memory>
#include <vector>

#include "cloth_sim/core/solvers/solver.h"

namespace cloth_sim {

/// One selectable solver.
struct SolverEntry {
  const char* name;         ///< what Solver::name() returns and scenes/parameters use
  const char* description;  ///< one line for users (dynamic_reconfigure, --help)
  std::unique_ptr<Solver> (*make)();
};

/// Every solver, in the order users see them (explicit baselines first, then the implicit ones).
const std::vector<SolverEntry>& solverRegistry();

}  // namespace cloth_sim
