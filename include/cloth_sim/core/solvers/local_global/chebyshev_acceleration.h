/// @file chebyshev_acceleration.h
/// Wang 2015, "A Chebyshev Semi-Iterative Approach for Accelerating Projective and
/// Position-based Dynamics", ACM TOG 34(6).
#pragma once

#include "cloth_sim/core/solvers/local_global/local_global_driver.h"
#include "cloth_sim/core/solvers/revision_cache.h"

namespace cloth_sim {

/// An upper bound on the spectral radius of local/global near a solution (springs at or above
/// their rest length) for a step of @p h s: mu / (1 + mu) with mu = h^2 max_i 2 d_i / m_i, d_i
/// the summed stiffness of particle i's springs (N/m), m_i its mass (kg). E.g. 0.9998 for the
/// 32 x 32 hanging cloth.
double localGlobalRhoBound(const Model& model, double h);

/// Chebyshev semi-iterative extrapolation of the local/global iterates (Wang 2015):
///   x_{k+1} = omega_{k+1} (gamma (xhat_{k+1} - x_k) + x_k - x_{k-1}) + x_{k-1},
///   omega = 1 for the first S iterations, 2 / (2 - rho^2) at S, then 4 / (4 - rho^2 omega)
/// (S = SolverSettings::chebyshev_delay, gamma = chebyshev_gamma). With chebyshev_rho = 0, rho
/// is the bound localGlobalRhoBound at SolverInput::h, recomputed when the revision changes (a
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
};

}  // namespace cloth_sim
