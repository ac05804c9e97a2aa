/// @file local_global_problem.h
/// The implicit Euler step as the local/global family sees it (Liu, Bargteil, O'Brien, Kavan
/// 2013): one prefactored scalar system, a node order, the local and global steps, g and its
/// gradient, and the contacts solved with the step.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "cloth_sim/core/linalg/node_buffer.h"
#include "cloth_sim/core/model/free_particles.h"
#include "cloth_sim/core/solvers/implicit_euler_problem.h"
#include "cloth_sim/core/solvers/local_global/global_system.h"
#include "cloth_sim/core/solvers/local_global/local_step.h"
#include "cloth_sim/core/solvers/revision_cache.h"
#include "cloth_sim/core/solvers/solver.h"

namespace cloth_sim {

class ContactForces;

/// A node buffer as one Eigen vector (padding included).
inline Eigen::Map<Eigen::VectorXd> asVector(NodeBuffer& v) {
  return Eigen::Map<Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
}
inline Eigen::Map<const Eigen::VectorXd> asVector(const NodeBuffer& v) {
  return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
}

/// The convergence measure of SolveResult for the local/global family:
/// |next - current| / |next - start| over whole node buffers (0 when next == start).
double relativeChange(const NodeBuffer& next, const NodeBuffer& current, const NodeBuffer& start);

/// One implicit Euler step of the mass-spring model, minimised by block coordinate descent on
/// the objective g (docs/method.md):
///  - local step: each spring's direction d_s = r_s (x_i - x_j) / |x_i - x_j|;
///  - global step: (M + h^2 L) x = M y + h^2 (J d + m g + soft-pin and boundary terms).
/// L = L_scalar (x) I3, so ONE scalar N_free x N_free sparse Cholesky factor serves x, y and z
/// (a three-column solve). The factor is kept across steps and recomputed only when the
/// SolverInput revision or SolverSettings::linear_solver changes (RevisionCache). Moving a pin
/// target only changes the right-hand side.
///
/// Everything lives in the factor's node order and a padded x, y, z, 0 layout (NodeBuffer):
/// free nodes first, hard-pinned nodes after them. An iteration is two streaming passes
/// (springs, then the fused triangular solves) and no permutation or gather; the contacts read
/// and write the same buffers (docs/benchmark.md, "Performance").
///
/// The solvers hold one (LocalGlobalSolver and its accelerations, LbfgsSolver); a step is
/// begin(), iterations, finishStep().
class LocalGlobalProblem {
 public:
  /// Refactors if the revision, the linear solver or the implicit step h_i changed (BDF2's
  /// first step is implicit Euler, h_i = h; the next ones have h_i = 2h/3); builds y and the
  /// constant part of
  /// the right-hand side; starts the contacts (SolverInput::contacts) in node order. Returns
  /// the numeric factorizations done (0 or 1).
  int begin(const SolverInput& input, const SolverSettings& settings, const State& state);
  /// One local + global iteration from @p x into @p x_next (hard pins kept at their targets),
  /// with the contact forces of @p x. Returns g(x), which the local step gets almost for free.
  /// It never raises g (without contacts): x_next minimises a quadratic upper bound of g.
  double iterate(const NodeBuffer& x, NodeBuffer& x_next);
  /// g(x) with one spring pass and no solve.
  double objectiveAt(const NodeBuffer& x) const;
  /// g(x) and its gradient over the free nodes (docs/method.md; Liu, Bouaziz, Kavan 2017, eq. 9):
  ///   grad g(x) = A x - b(x),  A = M + h^2 L (+ h^2 k on soft pins),
  ///   b(x) = M y + h^2 (J d(x) + m g + k_pin t + k x_boundary),
  /// with d(x) the local step's spring directions, so b is the global step's right-hand side.
  /// One spring pass and one sparse product with A; no solve. @p gradient gets the size of
  /// @p x, with zeros in the padding and in the rows of hard-pinned nodes. Contacts are ignored.
  double objectiveAndGradient(const NodeBuffer& x, NodeBuffer& gradient);
  /// v <- A^-1 v over the free nodes (the global step's factor; other rows untouched).
  void solveGlobal(NodeBuffer& v) { system_.solveInPlace(v.data()); }

  /// The inertial prediction y of this step, in node order.
  const NodeBuffer& inertial() const { return inertial_; }
  /// The first iterate: y, or with SolverSettings::warm_start y plus the previous step's
  /// correction x_n - y_{n-1} when that has the lower g.
  NodeBuffer initialGuess(const SolverSettings& settings) const;
  /// Ends the step: positions @p x, velocities (x - x_n) / h, time + h; keeps x - y.
  void finishStep(const NodeBuffer& x, State& state);
  /// @p out (3 x N, particle order) = the node buffer @p x.
  void toParticles(const NodeBuffer& x, Points& out) const;

  /// Whether this step solves contact forces (SolverInput::contacts was set).
  bool solvesContacts() const { return contacts_ != nullptr; }
  /// Free nodes: they come first in the node order, hard-pinned nodes after them.
  int freeNodeCount() const { return free_count_; }
  /// The global step's factored system (valid after the first begin).
  const GlobalSystem& system() const { return system_; }
  /// The springs as the local step sees them (valid after the first begin).
  const SpringTable& springTable() const { return springs_; }

 private:
  /// Factors A = M + h^2 L (@p h: the implicit step h_i, see ImplicitStepProblem), sets the
  /// node order and the node-ordered spring tables. Returns 0 or 1.
  int factorize(const SolverInput& input, LinearSolver backend, double h);
  double pinEnergy(const NodeBuffer& x) const;
  /// g(x) given the spring energy E(x) (J) of @p x: inertia, gravity, springs, soft pins.
  double objectiveWith(const NodeBuffer& x, double spring_energy) const;
  /// Per particle estimate of (A^-1)_ii (1/kg), 0 when pinned: the contacts' compliance.
  /// (after the node order is set; @p a in free-index order).
  void estimateCompliance(const Eigen::SparseMatrix<double>& a);
  /// Keeps @p a (free-index order) as node_matrix_: rows and columns in node order.
  void buildNodeMatrix(const Eigen::SparseMatrix<double>& a);

  /// A in node order over the free nodes, compressed rows (for objectiveAndGradient).
  struct NodeMatrix {
    std::vector<int> row_begin, column;
    std::vector<double> value;
  };

  RevisionCache factor_cache_;
  GlobalSystem system_;
  int free_count_ = 0;
  std::vector<int> node_particle_;  ///< node -> particle: free nodes in system order, then hard pins
  std::vector<int> particle_node_;  ///< particle -> node
  std::vector<double> node_mass_;   ///< kg, per node
  SpringTable springs_;             ///< springs with at least one free end
  FreeParticleMap dofs_;
  SpringTable pinned_springs_;      ///< springs with two pinned ends: constant energy
  double h_ = 0.0;                  ///< s, the implicit step h_i of this step
  Vec3 gravity_ = Vec3::Zero();
  int threads_ = 1;                 ///< the kernels' threads (SolverSettings::threads, resolved)

  ImplicitStepProblem problem_;
  NodeBuffer inertial_;             ///< y
  NodeBuffer rhs_constant_;         ///< M y + h^2 (m g + k_pin t + k x_boundary)
  NodeBuffer correction_;           ///< x_{n} - y of the previous step (warm start)
  double constant_energy_ = 0.0;    ///< springs between pinned nodes, J
  ContactForces* contacts_ = nullptr;  ///< this step's contact forces, or nullptr
  Eigen::VectorXd compliance_;         ///< per particle (1/kg), see estimateCompliance
  NodeMatrix node_matrix_;             ///< A in node order, built with the factor
  NodeBuffer rhs_work_;                ///< b(x) of objectiveAndGradient
};

}  // namespace cloth_sim
