#include "cloth_sim/core/solvers/local_global/local_global_solver.h"

namespace cloth_sim {

SolveResult LocalGlobalSolver::step(const SolverInput& input, const SolverSettings& settings,
                                    State& state) {
  factorizations_ += problem_.begin(input, settings, state);
  if (acceleration_ != nullptr) acceleration_->begin(input, settings);
  return runLocalGlobal(problem_, acceleration_, hooks_, settings, state, iterates_);
}

}  // namespace cloth_sim
