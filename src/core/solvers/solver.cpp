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

const char* integratorName(Integrator integrator) {
  switch (integrator) {
    case Integrator::kImplicitEuler: return "implicit_euler";
    case Integrator::kBdf2: return "bdf2";
  }
  return "unknown";
}

std::vector<std::string> integratorNames() {
  std::vector<std::string> names;
  for (Integrator i : kIntegrators) names.emplace_back(integratorName(i));
  return names;
}

Integrator integratorFromName(const std::string& name) {
  for (Integrator i : kIntegrators) {
    if (name == integratorName(i)) return i;
  }
  std::string list;
  for (const auto& n : integratorNames()) list += (list.empty() ? "" : ", ") + n;
  throw std::invalid_argument("unknown integrator '" + name + "' (known: " + list + ")");
}

void requireIntegrator(const Solver& solver, Integrator integrator) {
  if (solver.supports(integrator)) return;
  std::string implicit;
  for (const auto& n : solverNames()) {
    if (makeSolver(n)->supports(integrator)) implicit += (implicit.empty() ? "" : ", ") + n;
  }
  throw std::invalid_argument(std::string("solver.integrator = ") + integratorName(integrator) +
                              " is not supported by " + solver.name() +
                              " (an explicit scheme of its own; solvers that support it: " +
                              implicit + ")");
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
