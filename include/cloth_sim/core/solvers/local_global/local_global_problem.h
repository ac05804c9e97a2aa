/// @file local_global_problem.h
/// The implicit Euler step as the local/global family sees it (Liu, Bargteil, O'Brien, Kavan
/// 2013): one prefactored scalar system, a node order, the local and global steps, g and its
/// gradient, and the contacts solved with the step.
#pragma once

#include <Eigen/Core>
#include <chrono>
#include <cstdint>
#include <memory>
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
/// (a three-column solve). The factor is kept across steps, one per implicit step h_i used
/// (up to kKeptFactors), and recomputed only when the SolverInput revision or
/// SolverSettings::linear_solver changes. Moving a pin target only changes the right-hand side.
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
  void solveGlobal(NodeBuffer& v) { f_->system.solveInPlace(v.data()); }

  /// The inertial prediction y of this step, in node order.
  const NodeBuffer& inertial() const { return inertial_; }
  /// The first iterate: y, or with SolverSettings::warm_start y plus the previous step's
  /// correction x_n - y_{n-1} when that has the lower g.
  NodeBuffer initialGuess(const SolverSettings& settings) const;
  /// Ends the step: positions @p x, velocities (x - x_n) / h, time + h; keeps x - y.
  void finishStep(const NodeBuffer& x, State& state);
  /// @p out (3 x N, particle order) = the node buffer @p x.
  void toParticles(const NodeBuffer& x, Points& out) const;
  /// The warm start x_n - y of the last step in particle order (3 x N; empty when none) and
  /// the implicit step it is for.
  SolverCarry warmStart() const;
  /// Sets the warm start (as warmStart() gave it) that the next begin() uses, after its
  /// factorization, if its step has the same h_i (a snapshot restored into a fresh solver).
  void setWarmStart(const SolverCarry& carry) { pending_correction_ = carry; }

  /// Whether this step solves contact forces (SolverInput::contacts was set).
  bool solvesContacts() const { return contacts_ != nullptr; }
  /// m, RMS over the free nodes of |a_k - b_k|: the distance between two iterates.
  double rmsDistance(const NodeBuffer& a, const NodeBuffer& b) const;
  /// m, SolverInput::iteration_tolerance of this step (0: none).
  double iterationTolerance() const { return iteration_tolerance_; }
  /// Whether a step that has done @p done solves stops here for its SolverInput::deadline
  /// (SolverInput::pastDeadline).
  bool pastDeadline(int done) const {
    return done >= min_iterations_at_deadline_ &&
           deadline_ != std::chrono::steady_clock::time_point::max() &&
           std::chrono::steady_clock::now() >= deadline_;
  }
  /// Free nodes: they come first in the node order, hard-pinned nodes after them.
  int freeNodeCount() const { return f_ != nullptr ? f_->free_count : 0; }
  /// The global step's factored system (valid after the first begin).
  const GlobalSystem& system() const { return f_->system; }
  /// The springs as the local step sees them (valid after the first begin).
  const SpringTable& springTable() const { return f_->springs; }

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
  /// Keeps @p a (free-index order) as f_->node_matrix: rows and columns in node order.
  void buildNodeMatrix(const Eigen::SparseMatrix<double>& a);

  /// A in node order over the free nodes, compressed rows (for objectiveAndGradient).
  struct NodeMatrix {
    std::vector<int> row_begin, column;
    std::vector<double> value;
  };
  /// Everything a factorization sets, for one (revision, linear solver, implicit step h_i).
  struct Factored {
    std::uint64_t revision = 0;
    LinearSolver backend = LinearSolver::kFused;
    double implicit_h = 0.0;  ///< s
    GlobalSystem system;
    int free_count = 0;
    std::vector<int> node_particle;  ///< node -> particle: free nodes in system order, then pins
    std::vector<int> particle_node;  ///< particle -> node
    std::vector<double> node_mass;   ///< kg, per node
    SpringTable springs;             ///< springs with at least one free end (weights h_i^2 k r)
    FreeParticleMap dofs;
    SpringTable pinned_springs;      ///< springs with two pinned ends: constant energy
    Eigen::VectorXd compliance;      ///< per particle (1/kg), see estimateCompliance
    NodeMatrix node_matrix;          ///< A in node order
  };
  /// Factorizations kept: a run with error control moves between a few step sizes (and their
  /// variable-step BDF2 transitions), each factored once.
  static constexpr std::size_t kKeptFactors = 8;
  /// The factorization for @p revision, @p backend and @p h (made, or found among the kept
  /// ones; a new revision forgets them all) becomes f_. Returns the factorizations done (0, 1).
  int useFactor(const SolverInput& input, LinearSolver backend, double h);

  std::vector<std::unique_ptr<Factored>> factors_;  ///< most recently used last
  Factored* f_ = nullptr;                           ///< this step's
  double h_ = 0.0;                  ///< s, the implicit step h_i of this step
  double iteration_tolerance_ = 0.0;  ///< m, SolverInput::iteration_tolerance
  /// SolverInput::deadline of the step.
  std::chrono::steady_clock::time_point deadline_ = std::chrono::steady_clock::time_point::max();
  int min_iterations_at_deadline_ = 1;
  Vec3 gravity_ = Vec3::Zero();
  int threads_ = 1;                 ///< the kernels' threads (SolverSettings::threads, resolved)

  ImplicitStepProblem problem_;
  NodeBuffer inertial_;             ///< y
  NodeBuffer rhs_constant_;         ///< M y + h^2 (m g + k_pin t + k x_boundary)
  NodeBuffer correction_;           ///< x_{n} - y of the previous step (warm start)
  SolverCarry pending_correction_;  ///< setWarmStart's, for the next begin()
  double constant_energy_ = 0.0;    ///< springs between pinned nodes, J
  ContactForces* contacts_ = nullptr;  ///< this step's contact forces, or nullptr
  NodeBuffer rhs_work_;                ///< b(x) of objectiveAndGradient
};

}  // namespace cloth_sim
