/// @file explicit_solvers.h
/// The original report's integrators, kept as baselines to show where they fail: both are
/// conditionally stable, h < 2 / omega_max with omega_max^2 ~ 4 k_max / m_min per spring.
#pragma once

#include "cloth_sim/core/solvers/solver.h"

namespace cloth_sim {

/// Symplectic (semi-implicit) Euler: v += h F(x)/m; x += h v.
class ExplicitEulerSolver final : public Solver {
 public:
  const char* name() const override { return "explicit_euler"; }
  SolveResult step(const SolverInput& input, const SolverSettings& settings,
                   State& state) override;
};

/// Velocity Verlet: x += h v + h^2/2 a(x); v += h/2 (a(x_n) + a(x_{n+1})). Second order and
/// time-reversible; the same stability limit as symplectic Euler.
class VerletSolver final : public Solver {
 public:
  const char* name() const override { return "verlet"; }
  SolveResult step(const SolverInput& input, const SolverSettings& settings,
                   State& state) override;
};

}  // namespace cloth_sim
