/// @file local_global_3n_solver.h
/// The baseline layout of the original fast mass-spring code: one 3N x 3N factor.
#pragma once

#include <Eigen/SparseCholesky>

#include "cloth_sim/core/model/free_particles.h"
#include "cloth_sim/core/solvers/implicit_euler_problem.h"
#include "cloth_sim/core/solvers/revision_cache.h"
#include "cloth_sim/core/solvers/solver.h"

namespace cloth_sim {

/// Local/global exactly as LocalGlobalSolver (same iterates to round-off), but with the system
/// matrix in the layout of Liu et al.'s published code: (M + h^2 L) (x) I3 as one 3N x 3N
/// sparse matrix (x, y, z of a particle interleaved), factored by Eigen's SimplicialLLT (AMD),
/// one 3N right-hand side per solve, and the straightforward per-spring local step over Points.
///
/// It is kept as the measured baseline: "local_global" reads a factor a third of the size,
/// once per direction for all three coordinates, without permutations (docs/benchmark.md, "Performance").
class LocalGlobal3nSolver final : public Solver {
 public:
  const char* name() const override { return "local_global_3n"; }
  SolveResult step(const SolverInput& input, const SolverSettings& settings,
                   State& state) override;

 private:
  /// Factors M + h^2 L (x) I3, @p h the implicit step h_i (s).
  void factorize(const SolverInput& input, double h);

  RevisionCache factor_cache_;
  FreeParticleMap dofs_;
  Eigen::SimplicialLLT<Eigen::SparseMatrix<double>> factor_;
  Eigen::VectorXd rhs_, solution_;  // 3 N_free, interleaved x, y, z
};

}  // namespace cloth_sim
