#include "cloth_sim/core/solvers/registry.h"

#include <algorithm>
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

/// An explicit scheme of its own: no implicit integrator, nothing to iterate.
SolverCapabilities ownScheme() { return {{Integrator::kImplicitEuler}}; }

/// Minimises the implicit step's objective for every integrator, iterating to a tolerance;
/// @p contacts: solves the contact forces with the step; @p warm: honours warm_start.
SolverCapabilities implicitStep(bool contacts, bool warm) {
  return {{std::begin(kIntegrators), std::end(kIntegrators)}, contacts, warm, true, true};
}

}  // namespace

bool SolverCapabilities::supports(Integrator integrator) const {
  return std::find(integrators.begin(), integrators.end(), integrator) != integrators.end();
}

const std::vector<SolverEntry>& solverRegistry() {
  // Names and descriptions are also in registry.yaml (read by cfg/ClothSim.cfg), in this order.
  // clang-format off
  static const std::vector<SolverEntry> registry = {
      {"explicit_euler", "symplectic Euler (unstable on stiff cloth)", make<ExplicitEulerSolver>,
       ownScheme()},
      {"verlet", "velocity Verlet (unstable on stiff cloth)", make<VerletSolver>, ownScheme()},
      {"newton", "Newton on implicit Euler (accurate, slow)", make<NewtonSolver>,
       implicitStep(false, false)},
      {"local_global", "Liu et al. 2013 local/global", make<LocalGlobalSolver>,
       implicitStep(true, true)},
      {"chebyshev", "local/global with Chebyshev acceleration", make<ChebyshevSolver>,
       implicitStep(true, true),
       {&settings::kChebyshevRho, &settings::kChebyshevGamma, &settings::kChebyshevDelay}},
      {"anderson", "local/global with Anderson acceleration", make<AndersonSolver>,
       implicitStep(true, true), {&settings::kAndersonWindow}},
      {"lbfgs", "L-BFGS with the local/global matrix (Liu et al. 2017)", make<LbfgsSolver>,
       implicitStep(false, true), {&settings::kLbfgsWindow}},
      {"local_global_3n", "local/global, 3N x 3N factor (baseline)", make<LocalGlobal3nSolver>,
       implicitStep(false, false)},
      // Sweeps (iterations) but no convergence test: a tolerance and a warm start are refused.
      {"xpbd", "XPBD distance constraints, small steps (baseline)", make<XpbdSolver>,
       {{Integrator::kImplicitEuler}, false, false, true, false}},
  };
  // clang-format on
  return registry;
}

std::vector<std::string> solverNames() {
  std::vector<std::string> names;
  for (const SolverEntry& entry : solverRegistry()) names.emplace_back(entry.name);
  return names;
}

std::vector<std::string> solverNamesWith(bool SolverCapabilities::*capability) {
  std::vector<std::string> names;
  for (const SolverEntry& entry : solverRegistry()) {
    if (entry.capabilities.*capability) names.emplace_back(entry.name);
  }
  return names;
}

const SolverEntry* findSolver(const std::string& name) {
  for (const SolverEntry& entry : solverRegistry()) {
    if (name == entry.name) return &entry;
  }
  return nullptr;
}

const SolverEntry& solverEntry(const std::string& name) {
  if (const SolverEntry* entry = findSolver(name)) return *entry;
  std::string list;
  for (const auto& n : solverNames()) list += (list.empty() ? "" : ", ") + n;
  throw std::invalid_argument("unknown solver '" + name + "' (known: " + list + ")");
}

std::unique_ptr<Solver> makeSolver(const std::string& name) { return solverEntry(name).make(); }

}  // namespace cloth_sim
