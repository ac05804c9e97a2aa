#include "cloth_sim/core/solvers/solver.h"

#include <stdexcept>

#include "cloth_sim/core/settings/settings_table.h"

namespace cloth_sim {

const char* linearSolverName(LinearSolver solver) {
  switch (solver) {
    case LinearSolver::kFused: return "fused";
    case LinearSolver::kCholmod: return "cholmod";
    case LinearSolver::kEigen: return "eigen";
  }
  return "unknown";
}

std::vector<std::string> linearSolverNames() {
  std::vector<std::string> names;
  for (LinearSolver s : kLinearSolvers) names.emplace_back(linearSolverName(s));
  return names;
}

LinearSolver linearSolverFromName(const std::string& name) {
  for (LinearSolver s : kLinearSolvers) {
    if (name == linearSolverName(s)) return s;
  }
  std::string list;
  for (const auto& n : linearSolverNames()) list += (list.empty() ? "" : ", ") + n;
  throw std::invalid_argument("unknown linear solver '" + name + "' (known: " + list + ")");
}

void SolverSettings::validate() const {
  settings::kIterations.require(max_iterations);
  settings::kSubsteps.require(substeps);
  settings::kTolerance.require(tolerance);
  settings::kChebyshevRho.require(chebyshev_rho);
  settings::kChebyshevGamma.require(chebyshev_gamma);
  settings::kChebyshevDelay.require(chebyshev_delay);
  settings::kAndersonWindow.require(anderson_window);
  settings::kLbfgsWindow.require(lbfgs_window);
}

}  // namespace cloth_sim
