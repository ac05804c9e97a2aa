/// @file local_global_solver.h
/// Liu, Bargteil, O'Brien, Kavan 2013, "Fast Simulation of Mass-Spring Systems", ACM TOG 32(6).
#pragma once

#include <functional>
#include <vector>

#include "cloth_sim/core/model/free_particles.h"
#include "cloth_sim/core/solvers/implicit_euler_problem.h"
#include "cloth_sim/core/solvers/local_global/local_step.h"
#include "cloth_sim/core/solvers/local_global/global_system.h"
#include "cloth_sim/core/solvers/solver.h"

namespace cloth_sim {

/// Block coordinate descent on the implicit Euler objective g (docs/method.md):
///  - local step: each spring's direction d_s = r_s (x_i - x_j) / |x_i - x_j|;
///  - global step: (M + h^2 L) x = M y + h^2 (J d + m g + soft-pin and boundary terms).
/// L = L_scalar (x) I3, so ONE scalar N_free x N_free sparse Cholesky factor serves x, y and z
/// (a three-column solve). The factor is kept across steps and recomputed only when the
/// SolverInput revision or SolverSettings::linear_solver changes (h, a stiffness, a mass or the
/// pin set). Moving a pin target only changes the right-hand side.
///
/// Inside a step everything lives in the factor's node order and a padded x, y, z, 0 layout, so
/// an iteration is two streaming passes (springs, then the fused triangular solves) and no
/// permutation or gather (docs/benchmark.md, "Performance").
///
/// g never increases from one iterate to the next; the iterates converge (linearly) to the
/// implicit Euler solution that NewtonSolver finds. The initial guess is the inertial prediction y.
class LocalGlobalSolver : public Solver {
 public:
  const char* name() const override { return "local_global"; }
  SolveResult step(const SolverInput& input, const SolverSettings& settings,
                   State& state) override;

  /// Diagnostic hook (tests, benchmark): when set, every step clears it and appends g(x_k) for
  /// the initial guess and every iterate. Costs one spring pass per step. nullptr disables.
  void setObjectiveTrace(std::vector<double>* trace) { trace_ = trace; }

  /// Diagnostic hook (benchmark): called after iteration k (1, 2, ...) with the iterate x_k
  /// (m, all particles), the one the step would return if it stopped there; returning false
  /// stops the step there. Costs a conversion per iteration. An empty function disables.
  using IterateObserver = std::function<bool(int, const Points&)>;
  void setIterateObserver(IterateObserver observer) { observer_ = std::move(observer); }

  /// The global step's factored system (valid after the first step).
  const GlobalSystem& system() const { return system_; }
  /// The springs as the local step sees them (valid after the first step).
  const SpringTable& springTable() const { return springs_; }

 protected:
  /// Refactors if needed; builds y and the constant part of the right-hand side.
  void beginStep(const SolverInput& input, const SolverSettings& settings, const State& state);
  /// One local + global iteration from @p x into @p x_next (hard pins kept at their targets).
  /// Returns g(x), which the local step gets almost for free.
  double iterate(const NodeBuffer& x, NodeBuffer& x_next);
  /// g(x) with one spring pass and no solve.
  double objectiveAt(const NodeBuffer& x) const;
  /// The initial guess y of this step, in node order.
  const NodeBuffer& inertial() const { return inertial_; }
  /// The first iterate: y, or with SolverSettings::warm_start y plus the previous step's
  /// correction when that has the lower g.
  NodeBuffer initialGuess(const SolverSettings& settings) const;
  /// Ends the step: positions @p x, velocities (x - x_n) / h, time + h; keeps x - y.
  void finishStep(const NodeBuffer& x, State& state);
  /// Calls the observer; false if it asked to stop.
  bool observe(int k, const NodeBuffer& x) const;
  bool observing() const { return static_cast<bool>(observer_); }

  void recordTrace(double g) {
    if (trace_ != nullptr) trace_->push_back(g);
  }
  void clearTrace() {
    if (trace_ != nullptr) trace_->clear();
  }
  bool tracing() const { return trace_ != nullptr; }
  /// Whether this step solves contact forces (SolverInput::contacts was set).
  bool solvesContacts() const { return contacts_ != nullptr; }

  /// Free nodes: they come first in the node order, hard-pinned nodes after them.
  int freeNodeCount() const { return free_count_; }
  /// g(x) and its gradient over the free nodes (docs/method.md; Liu, Bouaziz, Kavan 2017, eq. 9):
  ///   grad g(x) = A x - b(x),  A = M + h^2 L (+ h^2 k on soft pins),
  ///   b(x) = M y + h^2 (J d(x) + m g + k_pin t + k x_boundary),
  /// with d(x) the local step's spring directions, so b is the global step's right-hand side.
  /// One spring pass and one sparse product with A; no solve. @p gradient gets the size of
  /// @p x, with zeros in the padding and in the rows of hard-pinned nodes. Contacts are ignored.
  double objectiveAndGradient(const NodeBuffer& x, NodeBuffer& gradient);
  /// v <- A^-1 v over the free nodes (the global step's factor; other rows untouched).
  void solveGlobal(NodeBuffer& v) { system_.solveInPlace(v.data()); }

 private:
  void factorize(const SolverInput& input, LinearSolver backend);
  double pinEnergy(const NodeBuffer& x) const;
  /// g(x) given the spring energy E(x) (J) of @p x: inertia, gravity, springs, soft pins.
  double objectiveWith(const NodeBuffer& x, double spring_energy) const;
  /// @p out (3 x N, particle order) = the node buffer @p x.
  void toParticles(const NodeBuffer& x, Points& out) const;
  /// Per particle estimate of (A^-1)_ii (1/kg), 0 when pinned: the contacts' compliance.
  /// (after the node order is set; @p a in free-index order).
  void estimateCompliance(const Eigen::SparseMatrix<double>& a);
  /// Contact forces of iterate @p x added to the right-hand side @p rhs (node order).
  void addContactForces(const NodeBuffer& x, NodeBuffer& rhs);
  /// Keeps @p a (free-index order) as node_matrix_: rows and columns in node order.
  void buildNodeMatrix(const Eigen::SparseMatrix<double>& a);

  /// A in node order over the free nodes, compressed rows (for objectiveAndGradient).
  struct NodeMatrix {
    std::vector<int> row_begin, column;
    std::vector<double> value;
  };

  std::uint64_t prepared_revision_ = 0;
  bool prepared_ = false;
  GlobalSystem system_;
  int free_count_ = 0;
  std::vector<int> node_particle_;  ///< node -> particle: free nodes in system order, then hard pins
  std::vector<int> particle_node_;  ///< particle -> node
  std::vector<double> node_mass_;   ///< kg, per node
  SpringTable springs_;             ///< springs with at least one free end
  FreeParticleMap dofs_;
  SpringTable pinned_springs_;      ///< springs with two pinned ends: constant energy
  double h_ = 0.0;
  Vec3 gravity_ = Vec3::Zero();

  ImplicitStepProblem problem_;
  NodeBuffer inertial_;             ///< y
  NodeBuffer rhs_constant_;         ///< M y + h^2 (m g + k_pin t + k x_boundary)
  NodeBuffer correction_;           ///< x_{n} - y of the previous step (warm start)
  double constant_energy_ = 0.0;    ///< springs between pinned nodes, J
  ContactForces* contacts_ = nullptr;  ///< this step's contact forces, or nullptr
  Eigen::VectorXd compliance_;         ///< per particle (1/kg), see estimateCompliance
  Points contact_x_, contact_rhs_;     ///< particle-order work buffers of the contacts
  NodeMatrix node_matrix_;             ///< A in node order, built with the factor
  NodeBuffer rhs_work_;                ///< b(x) of objectiveAndGradient
  mutable Points observed_;
  IterateObserver observer_;
  std::vector<double>* trace_ = nullptr;
};

/// The convergence measure of SolveResult for the local/global family:
/// |next - current| / |next - start| over whole node buffers (0 when next == start).
double relativeChange(const NodeBuffer& next, const NodeBuffer& current, const NodeBuffer& start);

/// An upper bound on the spectral radius of local/global near a solution (springs at or above
/// their rest length): mu / (1 + mu) with mu = h^2 max_i 2 d_i / m_i, d_i the summed stiffness
/// of particle i's springs (N/m), m_i its mass (kg). E.g. 0.9998 for the 32 x 32 hanging cloth.
double localGlobalRhoBound(const Model& model);

/// Local/global with Chebyshev semi-iterative acceleration (Wang 2015, "A Chebyshev
/// Semi-Iterative Approach for Accelerating Projective and Position-based Dynamics"):
///   x_{k+1} = omega_{k+1} (gamma (xhat_{k+1} - x_k) + x_k - x_{k-1}) + x_{k-1},
///   omega = 1 for the first S iterations, 2 / (2 - rho^2) at S, then 4 / (4 - rho^2 omega).
/// Safeguard: when an accelerated iterate raises g, it is replaced by the plain local/global
/// iterate (which never raises g) and the acceleration restarts; the returned iterate is never
/// worse than the last plain local/global one. With rho = 0 in the settings, rho is the bound
/// localGlobalRhoBound, recomputed when the revision changes (a stiffness, mass or h).
class ChebyshevSolver final : public LocalGlobalSolver {
 public:
  const char* name() const override { return "chebyshev"; }
  SolveResult step(const SolverInput& input, const SolverSettings& settings,
                   State& state) override;
  /// The spectral radius in use (measured or given).
  double rho() const { return rho_; }

 private:
  double rho_ = 0.0;
  std::uint64_t rho_revision_ = 0;
  bool rho_set_ = false;
};

/// Local/global with Anderson acceleration and an energy safeguard (Peng, Deng, Zhang, Liu 2018,
/// "Anderson Acceleration for Geometry Optimization and Physics Simulation", Algorithm 2).
/// One local/global iteration is a fixed-point map G; with residuals F_j = G(x_j) - x_j and
/// the last m differences dF_j = F_{j+1} - F_j, dG_j = G(x_{j+1}) - G(x_j) (m =
/// SolverSettings::anderson_window):
///   theta = argmin |F_k - dF theta|_2,   x_{k+1} = G(x_k) - dG theta.
/// Safeguard: g(x_{k+1}) comes with the next iteration (the local step computes it); when it
/// is above g(x_k), x_{k+1} is replaced by the plain iterate G(x_k) (g(G(x_k)) <= g(x_k)) and
/// the history is cleared, at the cost of one more solve. So g of the accepted iterates never
/// increases, and the returned iterate is never worse than the plain iterate it came from.
/// Per iteration it adds O(m n) vector work (n = 4 N doubles) to the local/global iteration.
class AndersonSolver final : public LocalGlobalSolver {
 public:
  const char* name() const override { return "anderson"; }
  SolveResult step(const SolverInput& input, const SolverSettings& settings,
                   State& state) override;
  /// Iterates rejected by the safeguard since construction (diagnostics, tests).
  int rejections() const { return rejections_; }

 private:
  /// Clears the history (after a rejection, and at the start of a step).
  void resetHistory();
  /// Appends dF = f - f_last, dG = g_map - g_map_last to the history (dropping the oldest
  /// beyond @p window) and keeps f, g_map as the last residual and map value.
  void pushHistory(const NodeBuffer& f, const NodeBuffer& g_map, int window);
  /// x = G(x_k) - dG theta with theta the least-squares coefficients for the residual @p f.
  void extrapolate(const NodeBuffer& f, const NodeBuffer& g_map, NodeBuffer& x) const;

  Eigen::MatrixXd d_f_, d_g_;  ///< columns: the last differences of F and G (a ring)
  Eigen::MatrixXd gram_;       ///< dF^T dF of the columns in use
  int history_ = 0;            ///< columns in use
  int next_column_ = 0;        ///< the ring's next column to overwrite
  NodeBuffer f_last_, g_last_;  ///< F and G of the previous accepted iterate
  bool has_last_ = false;
  int rejections_ = 0;
};

}  // namespace cloth_sim
