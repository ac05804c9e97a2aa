#include "cloth_sim/core/solvers/solver.h"

#include <cmath>
#include <stdexcept>

#include "cloth_sim/core/solvers/baselines/explicit_solvers.h"
#include "cloth_sim/core/solvers/baselines/local_global_3n_solver.h"
#include "cloth_sim/core/solvers/local_global/lbfgs_solver.h"
#include "cloth_sim/core/solvers/local_global/local_global_solver.h"
#include "cloth_sim/core/solvers/newton_solver.h"

namespace cloth_sim {

const char* linearSolverName(LinearSolver solver) {
  switch (solver) {
    case LinearSolver::kFused: return "fused";
    case LinearSolver::kCholmod: return "cholmod";
    case LinearSolver::kEigen: return "eigen";
  }
  return "unknown";
}

LinearSolver linearSolverFromName(const std::string& name) {
  for (LinearSolver s : {LinearSolver::kFused, LinearSolver::kCholmod, LinearSolver::kEigen}) {
    if (name == linearSolverName(s)) return s;
  }
  throw std::invalid_argument("unknown linear solver '" + name + "' (known: fused, cholmod, eigen)");
}

void SolverSettings::validate() const {
  if (max_iterations < 1) {
    throw std::invalid_argument("solver iterations = " + std::to_string(max_iterations) +
                                " must be >= 1");
  }
  if (!std::isfinite(tolerance) || tolerance < 0.0) {
    throw std::invalid_argument("solver tolerance must be finite and >= 0");
  }
  if (!std::isfinite(chebyshev_rho) || chebyshev_rho < 0.0 || chebyshev_rho >= 1.0) {
    throw std::invalid_argument("chebyshev rho = " + std::to_string(chebyshev_rho) +
                                " must be in [0, 1) (0 = measure it)");
  }
  if (!std::isfinite(chebyshev_gamma) || chebyshev_gamma <= 0.0 || chebyshev_gamma > 1.0) {
    throw std::invalid_argument("chebyshev gamma = " + std::to_string(chebyshev_gamma) +
                                " must be in (0, 1]");
  }
  if (chebyshev_delay < 1) {
    throw std::invalid_argument("chebyshev delay = " + std::to_string(chebyshev_delay) +
                                " must be >= 1");
  }
  if (anderson_window < 1 || anderson_window > 50) {
    throw std::invalid_argument("anderson window = " + std::to_string(anderson_window) +
                                " must be in [1, 50]");
  }
  if (lbfgs_window < 1 || lbfgs_window > 50) {
    throw std::invalid_argument("lbfgs window = " + std::to_string(lbfgs_window) +
                                " must be in [1, 50]");
  }
}

std::vector<std::string> solverNames() {
  return {"explicit_euler", "verlet",   "newton",
          "local_global",   "chebyshev", "anderson", "lbfgs", "local_global_3n"};
}

std::unique_ptr<Solver> makeSolver(const std::string& name) {
  if (name == "explicit_euler") return std::make_unique<ExplicitEulerSolver>();
  if (name == "verlet") return std::make_unique<VerletSolver>();
  if (name == "newton") return std::make_unique<NewtonSolver>();
  if (name == "local_global") return std::make_unique<LocalGlobalSolver>();
  if (name == "chebyshev") return std::make_unique<ChebyshevSolver>();
  if (name == "anderson") return std::make_unique<AndersonSolver>();
  if (name == "lbfgs") return std::make_unique<LbfgsSolver>();
  if (name == "local_global_3n") return std::make_unique<LocalGlobal3nSolver>();
  std::string list;
  for (const auto& n : solverNames()) list += (list.empty() ? "" : ", ") + n;
  throw std::invalid_argument("unknown solver '" + name + "' (known: " + list + ")");
}

}  // namespace cloth_sim
