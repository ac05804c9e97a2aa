/// @file solver.h
/// One interface for every time integrator, selectable by name.
#pragma once

#include <chrono>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "cloth_sim/core/model/model.h"
#include "cloth_sim/core/model/pins.h"
#include "cloth_sim/core/settings/settings_table.h"

namespace cloth_sim {

/// How local/global and chebyshev solve their global step (M + h^2 L) x = b, and how newton
/// factors its Hessian (kEigen: Eigen SimplicialLLT; the others: CHOLMOD supernodal). The double
/// ones give the same iterates to round-off; they differ in speed only (docs/benchmark.md,
/// "Performance").
enum class LinearSolver {
  kFused,    ///< CHOLMOD factor (AMD or METIS ordering), hand-written fused 3-column solves
  kCholmod,  ///< CHOLMOD factor and CHOLMOD's own solve, x, y and z as three columns
  kEigen,    ///< Eigen SimplicialLLT (AMD) and its solve: the first implementation, kept to compare
  /// kFused's factor rounded to float and solved in float, for a correction of the double
  /// residual: x_{k+1} = x_k + A_f^-1 (b(x_k) - A x_k). The same fixed point as kFused (the
  /// residual is exact), reached along iterates that differ from kFused's by about 1e-7
  /// relative; newton treats it as kFused (docs/method.md, "Single-precision factor").
  kFusedFloat,
};
/// Every LinearSolver, in the order of the enum.
inline constexpr LinearSolver kLinearSolvers[] = {LinearSolver::kFused, LinearSolver::kCholmod,
                                                  LinearSolver::kEigen, LinearSolver::kFusedFloat};
/// "fused", "cholmod", "eigen", "fused_float".
const char* linearSolverName(LinearSolver solver);
/// The names of kLinearSolvers.
std::vector<std::string> linearSolverNames();
/// The LinearSolver called @p name; throws std::invalid_argument listing the names if unknown.
LinearSolver linearSolverFromName(const std::string& name);

/// The time discretisation the implicit solvers minimise (docs/method.md, "BDF2").
enum class Integrator {
  /// x_{n+1} = argmin 1/2 |x - y|_M^2 + h^2 E(x), y = x_n + h v_n: first order, and its
  /// numerical damping removes the fast modes' energy within a few steps.
  kImplicitEuler,
  /// Second-order backward differentiation: x_{n+1} = argmin 1/2 |x - y|_M^2 + (4/9) h^2 E(x),
  /// y from the two last states; far less numerical damping, same kind of matrix.
  kBdf2,
  /// Implicit midpoint: an implicit Euler step of h/2, x_half = argmin 1/2 |x - y|_M^2 +
  /// (h/2)^2 E(x) with y = x_n + (h/2) v_n, then the explicit half x_{n+1} = 2 x_half - x_n,
  /// v_{n+1} = 4 (x_half - x_n) / h - v_n. Second order and symplectic: no numerical damping
  /// (|z| = 1 on a linear oscillator), its own matrix M + (h/2)^2 L.
  kImplicitMidpoint,
};
/// Every Integrator, in the order of the enum.
inline constexpr Integrator kIntegrators[] = {Integrator::kImplicitEuler, Integrator::kBdf2,
                                              Integrator::kImplicitMidpoint};
/// "implicit_euler", "bdf2", "implicit_midpoint".
const char* integratorName(Integrator integrator);
/// The names of kIntegrators.
std::vector<std::string> integratorNames();
/// The Integrator called @p name; throws std::invalid_argument listing the names if unknown.
Integrator integratorFromName(const std::string& name);

/// A setting of one solver only, in its registry entry's block (solvers/registry.h; the scene's
/// solver.<solver>.<field>): a Setting (name "solver.<solver>.<field>", range, unit, note, doc)
/// and the value a solver uses when none is given. It is declared with its solver (e.g.
/// settings::kChebyshevRho in chebyshev_acceleration.h), so that a solver's settings stay in
/// solvers/.
struct SolverParam : Setting {
  double default_value;  ///< in the setting's unit; allowed by it (tested)

  /// The field within the solver's block: the name after "solver.<solver>." ("rho").
  std::string field() const;
};

/// Values of per-solver settings (SolverParam), each read by its solver with number() or
/// integer(); one that was never set reads as its default. Values for any solver may be held
/// (a scene may give the chebyshev block and run local_global): only the solver that declares a
/// setting reads it.
class SolverParams {
 public:
  /// The value of @p param (its unit): the one set, else param.default_value.
  double number(const SolverParam& param) const;
  /// number(param) as an int, for an integer setting (param.integer).
  int integer(const SolverParam& param) const;
  /// Gives @p param the value @p value, checked by validate() as every SolverSettings field.
  void set(const SolverParam& param, double value);
  /// Throws std::invalid_argument (Setting::require, named by the setting's name) for the first
  /// value its setting refuses.
  void validate() const;

 private:
  /// The values set, in the order first set.
  std::vector<std::pair<const SolverParam*, double>> values_;
};

/// Iteration controls shared by the solvers (each uses what applies to it: its registry entry's
/// capabilities, solvers/registry.h), and the values of the per-solver settings. The allowed
/// range of each field is its entry in settings/settings_table.h (settings::kIterations, ...).
struct SolverSettings {
  /// Iterations per step: local/global and chebyshev run exactly this many unless tolerance
  /// stops them first; newton uses it as a cap. Ignored by the explicit solvers.
  int max_iterations = 10;
  /// Implicit steps per frame: Simulation::step advances the frame time_step as this many steps
  /// of time_step / substeps (read by Simulation; a solver sees one step of SolverInput::h).
  /// Smaller steps damp less and resolve contact better; see docs/method.md, "Substeps".
  int substeps = 1;
  /// Stop when the convergence measure (relative position change of the last iteration, see
  /// SolveResult) drops below this. 0 = always run max_iterations (fixed real-time cost).
  double tolerance = 0.0;
  /// The per-solver settings (chebyshev's rho, gamma and delay, anderson's and lbfgs's
  /// window, ...: each solver's registry entry lists its own).
  SolverParams params;
  /// The solvers whose capabilities have warm_start (the local/global family): start each step
  /// from y + (x_n - y_{n-1}), the previous step's correction, instead of y, whenever that
  /// start has the lower objective g. Motion is coherent from step to step, so the correction
  /// (what the springs did to the inertial prediction) changes little: fewer iterations for the
  /// same error.
  bool warm_start = false;
  /// How the linear systems are solved (same result, different speed), see LinearSolver.
  LinearSolver linear_solver = LinearSolver::kFused;
  /// Threads of the step's kernels (scene field solver.threads, settings::kThreads; 0 = every
  /// core the process may use). The work is split in blocks fixed by the problem, never by
  /// this count, so the result is the same to the bit for any value (docs/architecture.md,
  /// "Threads").
  int threads = 0;
  /// The time discretisation (scene field solver.integrator). The implicit solvers all minimise
  /// the same ImplicitStepProblem for it; the explicit baselines refuse kBdf2 and
  /// kImplicitMidpoint.
  Integrator integrator = Integrator::kImplicitEuler;
  /// m: the position error a frame may make (RMS over the particles), read by Simulation. > 0
  /// turns on error control: each step iterates until its estimated iteration error is under a
  /// share of it (max_iterations is then a cap), and with substeps 0 the substeps follow the
  /// estimated truncation error (docs/method.md, "Error control"). 0: fixed counts.
  double error_tolerance = 0.0;

  /// Whether the substeps are chosen by the error estimate (substeps 0, error_tolerance > 0).
  bool automaticSubsteps() const { return substeps == 0; }

  /// Throws std::invalid_argument naming the first field out of its range
  /// ("solver.iterations 0 must be in [1, 100000]", Setting::refusal).
  void validate() const;
};

/// What a solver did in one step.
struct SolveResult {
  int iterations = 0;        ///< iterations done (1 for the explicit solvers)
  /// Relative position change of the last iteration, |x_k - x_{k-1}| / |x_k - x_0| (x_0 the
  /// initial guess); 0 for the explicit solvers.
  double convergence = 0.0;
  bool converged = false;    ///< tolerance reached (always false when tolerance is 0)
  /// The solver solved SolverInput::contacts with the step (local_global, chebyshev and
  /// anderson do when given contacts; the others never do).
  bool used_contacts = false;
  /// The step gained energy under implicit midpoint and was redone as two implicit Euler steps
  /// of h/2 (MidpointSafeguard; no bare solver sets it).
  bool midpoint_fallback = false;
  /// m: the estimated distance of the returned positions to the step's exact solution, RMS over
  /// the free particles (IterationError; docs/method.md, "Error control"); 0 for the explicit
  /// solvers, which have nothing to converge.
  double iteration_error = 0.0;
  /// The iterations stopped at SolverInput::deadline, before their count or tolerance.
  bool cut = false;
};

/// The iteration error of a linearly converging iteration, from its position changes: with the
/// change d_k = RMS |x_{k+1} - x_k| (m) and the observed rate rho = d_k / d_{k-1}, the distance
/// to the fixed point is about d_k rho / (1 - rho) (a geometric tail). rho is capped at kMaxRate
/// (a slow or stalled iteration is not trusted to be nearly done). The first change is the move
/// away from the initial guess (the inertial prediction or the warm start), whose error the first
/// iteration mostly removes in the fast modes, so d_2 / d_1 is far below the rate of the slow
/// modes that remain: no rate is read from it, and the estimate is infinite until the third
/// change (kFirstTrusted), unless a change is exactly 0 (the fixed point itself).
class IterationError {
 public:
  static constexpr double kMaxRate = 0.95;
  /// The first change whose rate (d_k / d_{k-1}, k >= 3) the estimate trusts.
  static constexpr int kFirstTrusted = 3;
  /// Records the change of one more iteration (m); returns the estimate (m).
  double add(double change);
  /// The last estimate (m), infinity before kFirstTrusted changes.
  double estimate() const { return estimate_; }

 private:
  int changes_ = 0;
  double last_change_ = -1.0;
  double estimate_ = std::numeric_limits<double>::infinity();
};

class ContactForces;

/// The parts of the world a solver reads besides the state.
struct SolverInput {
  /// Every field but the contacts is required (a constructor, so that no caller forgets h).
  SolverInput(const Model& model, const PinSet& pins, double h, std::uint64_t revision,
              ContactForces* contacts = nullptr)
      : model(model), pins(pins), h(h), revision(revision), contacts(contacts) {}

  const Model& model;
  const PinSet& pins;
  /// m: stop iterating once SolveResult::iteration_error is at most this (0: run the settings'
  /// iterations). Simulation sets it from SolverSettings::error_tolerance per substep.
  double iteration_tolerance = 0.0;
  /// s, the step h the solver advances the state by: the frame time / substeps in Simulation
  /// (h/2 in the implicit midpoint safeguard's fallback). The model holds no step of its own.
  double h;
  /// Bumped whenever h, a stiffness, a mass, the set of pins or SolverSettings::integrator
  /// changes: a solver holding a factorization refactors when it sees a new value (or, within
  /// a BDF2 run, a new implicit step h_i: see RevisionCache), and only then.
  std::uint64_t revision;
  /// Contact forces to solve with the step, or nullptr. Only local_global, chebyshev and anderson
  /// use them (lbfgs, newton, local_global_3n and the explicit solvers ignore them; Simulation
  /// then resolves contacts after the step).
  ContactForces* contacts = nullptr;
  /// Wall-clock time after which an iterative solver stops iterating (after its first
  /// min_iterations_at_deadline iterations) and says so (SolveResult::cut): Simulation's frame
  /// deadline, so that no setting holds the caller for longer than that. max(): never (the
  /// default: same results on any machine).
  std::chrono::steady_clock::time_point deadline = std::chrono::steady_clock::time_point::max();
  /// Iterations a step keeps past the deadline (>= 1): more in the steps a deadline leaves to
  /// self-contact (Simulation::kDeadlineSelfContactIterations).
  int min_iterations_at_deadline = 1;
  /// Whether a solver that has done @p done iterations stops here for the deadline.
  bool pastDeadline(int done) const {
    return done >= min_iterations_at_deadline &&
           deadline != std::chrono::steady_clock::time_point::max() &&
           std::chrono::steady_clock::now() >= deadline;
  }
};

/// What a solver's step carries over to the next besides the State: its warm start, x - y of the
/// last step (m, 3 x N in particle order; empty: none), valid for the implicit step it was made
/// with (s, the h_i of ImplicitStepProblem; a step of another h_i starts cold).
struct SolverCarry {
  Points correction;        ///< m, x - y of the last step, 3 x N (empty: no warm start)
  double implicit_h = 0.0;  ///< s, the h_i of the step it was made with
};

/// A time integrator for the mass-spring model. It moves @c state by one step of
/// SolverInput::h (pins at their current targets, no collision: Simulation resolves those).
class Solver {
 public:
  virtual ~Solver() = default;
  /// Name used to select it (its entry in solverRegistry(), solvers/registry.h).
  virtual const char* name() const = 0;
  /// Advances @p state by one step. May leave non-finite values on blow-up: the caller checks.
  virtual SolveResult step(const SolverInput& input, const SolverSettings& settings,
                           State& state) = 0;
  /// Whether step() can integrate with @p integrator: its registry entry's capabilities (the
  /// explicit solvers and xpbd only know their own scheme).
  bool supports(Integrator integrator) const;
  /// Throws std::invalid_argument naming the field when step() cannot honour @p settings
  /// (Simulation checks it before a solver or its settings are used). By default: the
  /// integrator (requireIntegrator).
  virtual void requireSettings(const SolverSettings& settings) const;
  /// Sparse matrix factorizations done so far (numeric ones; Newton does one per iteration).
  /// Virtual for a wrapper (MidpointSafeguard), which counts its inner solver's.
  virtual int factorizationCount() const { return factorizations_; }
  /// What a step carries over to the next besides the State (Simulation::snapshot).
  virtual SolverCarry carriedOver() const { return SolverCarry(); }
  /// Gives a fresh solver what carriedOver() returned.
  virtual void carryOver(const SolverCarry& /*carry*/) {}

 protected:
  int factorizations_ = 0;
};

/// Throws std::invalid_argument ("solver.integrator = bdf2 is not supported by verlet; ...")
/// unless @p solver supports @p integrator.
void requireIntegrator(const Solver& solver, Integrator integrator);

/// Throws std::invalid_argument unless @p solver can honour @p settings' error control
/// (SolverSettings::error_tolerance > 0 needs a solver that iterates to a tolerance).
void requireErrorControl(const Solver& solver, const SolverSettings& settings);

/// The names makeSolver accepts, from solverRegistry() (solvers/registry.h).
std::vector<std::string> solverNames();
/// A new solver by name; throws std::invalid_argument listing the valid names if unknown.
std::unique_ptr<Solver> makeSolver(const std::string& name);

}  // namespace cloth_sim
