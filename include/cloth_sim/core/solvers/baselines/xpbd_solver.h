/// @file xpbd_solver.h
/// XPBD distance constraints with small steps: the peers' real-time baseline, run on the same
/// model, pins and scene as the implicit solvers (docs/method.md, "XPBD baseline").
#pragma once

#include <cstdint>
#include <vector>

#include "cloth_sim/core/linalg/types.h"
#include "cloth_sim/core/solvers/solver.h"

namespace cloth_sim {

/// Extended position-based dynamics (Macklin, Mueller, Chentanez 2016, "XPBD: Position-Based
/// Simulation of Compliant Constrained Dynamics", Algorithm 1) with every spring s = (i, j) a
/// distance constraint C_s(x) = |x_i - x_j| - r_s of compliance alpha_s = 1 / k_s (m/N), so its
/// potential 1/(2 alpha) C^2 is the spring's Hooke energy; each soft pin a zero-rest-length
/// constraint x_p - t_p of compliance 1 / k_p. One step of h (a substep of the frame):
///
///   v <- exp(-gamma h) v + h g;   p <- x + h v                    (prediction, free particles)
///   lambda <- 0; then settings.max_iterations Gauss-Seidel sweeps over the springs, colour
///   by colour (see below), each spring updating p in place:
///     alpha~ = alpha_s / h^2                                          (eq. 4)
///     dlambda = (-C_s(p) - alpha~ lambda_s) / (w_i + w_j + alpha~)    (eq. 18, grad C unit)
///     p_i += w_i dlambda n,  p_j -= w_j dlambda n,  n = (p_i - p_j) / |p_i - p_j|
///   v <- (p - x) / h;  x <- p
///
/// The sweep's order is that of PositionBasedDynamics (Bender et al., the peers' reference,
/// SimulationModel::initConstraintGroups): the springs are coloured greedily in model order
/// (first colour none of whose springs shares a particle with it) and solved colour after
/// colour, so no particle is corrected twice within a colour. Model order (particle by
/// particle, row by row) carried each correction along whole rows and columns of the grid
/// within one sweep; on a stiff cloth (k h^2 / m ~ 570: hanging at 128 x 128, 4 substeps)
/// that overshot and grew without bound (max strain 4e5, speeds 8e5 m/s at 1 s), where the
/// colour order stays finite (super-elastic at few substeps, as XPBD is: docs/method.md).
///
/// w_i = 1 / m_i, and 0 for a hard-pinned particle (infinite mass), which sits on its target.
/// With max_iterations = 1 this is Macklin et al. 2019 ("Small Steps in Physics Simulation"):
/// many substeps of one sweep each, the configuration the peers measured. Each correction
/// moves the two ends by w_i dlambda and -w_j dlambda, so linear momentum is conserved exactly
/// without pins and gravity. Contacts are left to Simulation's projection after the step
/// (SolveResult::used_contacts false). Single-threaded.
///
/// It integrates with its own scheme: kBdf2 and kImplicitMidpoint are refused (supports(), from
/// its registry entry), and
/// step() refuses a tolerance or a warm start, which it has no use for, naming the field.
class XpbdSolver final : public Solver {
 public:
  const char* name() const override { return "xpbd"; }
  /// Throws std::invalid_argument naming the field for solver.integrator = bdf2 or
  /// implicit_midpoint, solver.tolerance > 0 or solver.warm_start = true.
  void requireSettings(const SolverSettings& settings) const override;
  /// One step of SolverInput::h (requireSettings first).
  SolveResult step(const SolverInput& input, const SolverSettings& settings,
                   State& state) override;
  /// Colours of the sweep order after the last step (0 before the first): 13 on a grid with
  /// structural, shear (both diagonals) and bending springs.
  int colourCount() const { return colours_; }

 private:
  /// Rebuilds inverse masses, compliances and the colour order when the revision, h or the
  /// model's size change.
  void prepare(const SolverInput& input);

  std::uint64_t revision_ = ~std::uint64_t{0};
  double h_ = 0.0;
  std::size_t particles_ = 0, springs_ = 0;
  std::vector<double> inverse_mass_;    ///< 1/kg, 0 for hard-pinned particles
  std::vector<double> alpha_tilde_;     ///< 1/kg: 1 / (k_s h^2); 0 stiffness: no constraint (< 0)
  std::vector<double> lambda_;          ///< kg m (N s^2), per spring, this step's multipliers
  std::vector<int> order_;              ///< the springs to solve, colour by colour (see above)
  int colours_ = 0;                     ///< colours of order_
  std::vector<Vec3> pin_lambda_;        ///< kg m, per pin (soft pins only), this step's
  Points start_;                        ///< m, x at the start of the step
};

}  // namespace cloth_sim
