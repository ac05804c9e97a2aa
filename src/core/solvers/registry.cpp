#include "cloth_sim/core/solvers/registry.h"

#include <stdexcept>

#include "cloth_sim/core/solvers/baselines/explicit_solvers.h"
#include "cloth_sim/core/solvers/baselines/local_global_3n_solver.h"
#include "cloth_sim/core/solvers/baselines/xpbd_solver.h"
#include "cloth_sim/core/solvers/local_global/lbfgs_solver.h"
#include "cloth_sim/core/solvers/local_global/local_global_solver.h"
#include "cloth_sim/core/solvers/newton_solver.h"

namespace cloth_sim {
namespace {

template <class S>
std::unique_ptr<Solver> make() {
  return std::make_unique<S>();
}

}  // namespace

const std::vector<SolverEntry>& solverRegistry() {
  static const std::vector<SolverEntry> registry = {
      {"explicit_euler", "symplectic Euler (unstable on stiff cloth)", make<ExplicitEulerSolver>},
      {"verlet", "velocity Verlet (unstable on stiff cloth)", make<VerletSolver>},
      {"newton", "Newton on implicit Euler (accurate, slow)", make<NewtonSolver>},
      {"local_global", "Liu et al. 2013 local/global", make<LocalGlobalSolver>},
      {"chebyshev", "local/global with Chebyshev acceleration", make<ChebyshevSolver>},
      {"anderson", "local/global with Anderson acceleration", make<AndersonSolver>},
      {"lbfgs", "L-BFGS with the local/global matrix (Liu et al. 2017)", make<LbfgsSolver>},
      {"local_global_3n", "local/global, 3N x 3N factor (baseline)", make<LocalGlobal3nSolver>},
      {"xpbd", "XPBD distance constraints, small steps (baseline)", make<XpbdSolver>},
  };
  return registry;
}

std::vector<std::string> solverNames() {
  std::vector<std::string> names;
  for (const SolverEntry& entry : solverRegistry()) names.emplace_back(entry.name);
  return names;
}

std::unique_ptr<Solver> makeSolver(const std::string& name) {
  for (const SolverEntry& entry : solverRegistry()) {
    if (name == entry.name) return entry.make();
  }
  std::string list;
  for (const auto& n : solverNames()) list += (list.empty() ? "" : ", ") + n;
  throw std::invalid_argument("unknown solver '" + name + "' (known: " + list + ")");
}

}  // namespace cloth_sim
