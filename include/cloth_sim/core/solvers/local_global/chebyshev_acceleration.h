/// @file chebyshev_acceleration.h
/// Wang 2015, "A Chebyshev Semi-Iterative Approach for Accelerating Projective and
/// Position-based Dynamics", ACM TOG 34(6).
#pragma once

#include "cloth_sim/core/solvers/local_global/local_global_driver.h"
#include "cloth_sim/core/solvers/revision_cache.h"

namespace cloth_sim {

namespace settings {
// clang-format off
/// chebyshev: spectral radius rho of plain local/global, < 1. 0 = the upper bound
/// localGlobalRhoBound (an overestimate only slows the acceleration down; an underestimate, as
/// the former measured value was, makes the slow modes grow until the safeguard restarts).
inline constexpr SolverParam kChebyshevRho{{"solver.chebyshev.rho",   "", Range{0, 1, false, true}, false, "", "(0 = the upper bound)", "Spectral radius of plain local/global", 0}, 0.0};
/// chebyshev: under-relaxation gamma of Wang 2015, at most 1. 1 (none) converged 5-30 % faster
/// than Wang's 0.9 on the benchmark scenes.
inline constexpr SolverParam kChebyshevGamma{{"solver.chebyshev.gamma", "", Range{0, 1, true, false}, false, "", "", "Under-relaxation of Wang 2015", 0}, 1.0};
/// chebyshev: plain local/global iterations before the acceleration starts (Wang's S).
inline constexpr SolverParam kChebyshevDelay{{"solver.chebyshev.delay", "", Range::closed(1, 1000), true, "", "", "Plain iterations before the acceleration starts", 0}, 3};
// clang-format on
}  // namespace settings

/// An upper bound on the spectral radius of local/global near a solution (springs at or above
/// their rest length) for a step of @p h s: mu / (1 + mu) with mu = h^2 max_i 2 d_i / m_i, d_i
/// the summed stiffness of particle i's springs (N/m), m_i its mass (kg). E.g. 0.9998 for the
/// 32 x 32 hanging cloth.
double localGlobalRhoBound(const Model& model, double h);

/// Chebyshev semi-iterative extrapolation of the local/global iterates (Wang 2015):
///   x_{k+1} = omega_{k+1} (gamma (xhat_{k+1} - x_k) + x_k - x_{k-1}) + x_{k-1},
///   omega = 1 for the first S iterations, 2 / (2 - rho^2) at S, then 4 / (4 - rho^2 omega)
/// (S = settings::kChebyshevDelay, gamma = kChebyshevGamma). With kChebyshevRho 0, rho is the
/// bound localGlobalRhoBound at SolverInput::h, recomputed when the revision changes (a
/// stiffness, a mass or h). A restart (the driver's safeguard) begins the S plain iterations again.
class ChebyshevAcceleration final : public Acceleration {
 public:
  void begin(const SolverInput& input, const SolverSettings& settings) override;
  void restart() override { since_restart_ = 0; }
  bool extrapolate(const NodeBuffer& x_prev, const NodeBuffer& x, const NodeBuffer& x_hat,
                   NodeBuffer& x_next) override;
  /// The spectral radius in use (given or the bound).
  double rho() const { return rho_; }

 private:
  double rho_ = 0.0;
  RevisionCache rho_cache_;  ///< for the bound
  double gamma_ = 1.0;
  int delay_ = 1;
  double omega_ = 1.0;
  int since_restart_ = 0;  ///< accepted iterations since the (re)start
  int threads_ = 1;        ///< SolverSettings::threads, resolved
};

}  // namespace cloth_sim
