/// @file global_system.h
/// The global step's scalar system of local/global (Liu et al. 2013, eq. 12), factored once.
#pragma once

#include <vector>

#include <Eigen/SparseCholesky>

#include "cloth_sim/core/linalg/cholmod_factor.h"
#include "cloth_sim/core/model/free_particles.h"
#include "cloth_sim/core/solvers/solver.h"
#include "cloth_sim/core/linalg/supernodal_solves.h"

namespace cloth_sim {

/// A = M + h^2 L_scalar (plus h^2 k on soft-pinned nodes) over the free nodes: N_free x N_free,
/// symmetric positive definite, shared by x, y and z. Factored once per revision; each solve
/// takes the three coordinates at once in the padded node layout (kNodeStride doubles/node).
class GlobalSystem {
 public:
  /// Factors @p a (free-node order, both triangles stored) with @p backend. Throws
  /// std::runtime_error if @p a is not positive definite (it always is: masses are > 0).
  void factor(const Eigen::SparseMatrix<double>& a, LinearSolver backend);

  /// Row k of the buffers solveInPlace works on holds free node order()[k]: the factor's
  /// fill-reducing order for kFused (no permutation at solve time), the identity otherwise
  /// (the library permutes inside its solve).
  const std::vector<int>& order() const { return order_; }
  int size() const { return static_cast<int>(order_.size()); }
  LinearSolver backend() const { return backend_; }

  /// Threads of the fused solves (kFused, kFusedFloat; SolverSettings::threads resolved): the
  /// factor's split (splitSolves) runs on them, with the same result for any count.
  void setThreads(int threads) { threads_ = threads; }

  /// Solves A X = B in place; @p x holds size() nodes in order(), kNodeStride doubles each.
  /// kFusedFloat solves in float (about 1e-7 relative).
  void solveInPlace(double* x);

  /// The global step from the iterate @p x (size() nodes in order()): @p b holds the
  /// right-hand side b(x) on entry and the next iterate on exit. A^-1 b for the double
  /// backends; for kFusedFloat x + A_f^-1 (b - A x), the double residual solved in float, so
  /// that a fixed point (b(x) = A x) is the double one.
  void globalStep(const double* x, double* b);

  /// The explicit factor used by kFused and kFusedFloat (empty for the other backends).
  const SupernodalFactor& supernodal() const { return supernodal_; }
  /// kFusedFloat's factor in float (empty for the other backends).
  const SupernodalFactorF& supernodalFloat() const { return single_; }
  /// Nonzeros of the factor L, diagonal included.
  long factorNonZeros() const { return factor_nonzeros_; }

 private:
  /// Keeps @p a (free-index order) by rows in node order: kFusedFloat's residual.
  void keepNodeMatrix(const Eigen::SparseMatrix<double>& a);

  LinearSolver backend_ = LinearSolver::kFused;
  std::vector<int> order_;
  CholmodFactor cholmod_;
  SupernodalFactor supernodal_;
  Eigen::SimplicialLLT<Eigen::SparseMatrix<double>> eigen_;
  Eigen::MatrixX3d columns_, solution_;  // library backends: x, y, z as three columns
  long factor_nonzeros_ = 0;
  int threads_ = 1;
  // kFusedFloat: the float factor, its work buffer and A in node order (rows of the residual).
  SupernodalFactorF single_;
  std::vector<float> single_work_;
  std::vector<int> row_begin_, column_;
  std::vector<double> value_;
};

/// The global step's matrix M + h^2 L_scalar (+ h^2 k on soft-pinned particles) over the free
/// particles of @p dofs, in free-index order. A spring to a hard-pinned particle keeps only its
/// diagonal term; its coupling goes to the right-hand side (globalStepConstant). @p h is the
/// implicit step h_i of ImplicitStepProblem (s): SolverInput::h for implicit Euler, 2/3 of it
/// for BDF2.
Eigen::SparseMatrix<double> globalStepMatrix(const Model& model, const PinSet& pins,
                                             const FreeParticleMap& dofs, double h);

/// The part of the global step's right-hand side that is constant within a step, per particle
/// (3 x N, N m): M y + h^2 (m g + k_pin t), plus h^2 k y_p on the free end of every spring whose
/// other end p is hard-pinned. Rows of hard-pinned particles are meaningless.
Points globalStepConstant(const Model& model, const PinSet& pins, const FreeParticleMap& dofs,
                          double h,
                          const Points& inertial);

}  // namespace cloth_sim
