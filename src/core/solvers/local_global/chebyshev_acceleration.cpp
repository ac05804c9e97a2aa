#include "cloth_sim/core/solvers/local_global/chebyshev_acceleration.h"

#include <algorithm>
#include <vector>

namespace cloth_sim {

double localGlobalRhoBound(const Model& model, double h) {
  // Linearised, one local/global iteration maps an error e to (M + h^2 L)^-1 B e with
  // 0 <= B <= h^2 L (x) I3 for springs at or above rest length (B keeps the transverse part of
  // each spring's stiffness, scaled by r/l). Its spectral radius is therefore at most
  // mu / (1 + mu), mu = h^2 lambda_max(M^-1 L) <= h^2 max_i 2 d_i / m_i (Gershgorin; d_i the
  // stiffness summed over particle i's springs). On a grid the bound is tight.
  std::vector<double> degree(model.particleCount(), 0.0);
  for (std::size_t s = 0; s < model.springs.size(); ++s) {
    degree[model.springs.first[s]] += model.springs.stiffness[s];
    degree[model.springs.second[s]] += model.springs.stiffness[s];
  }
  double ratio = 0.0;
  for (int i = 0; i < model.particleCount(); ++i) ratio = std::max(ratio, 2.0 * degree[i] / model.mass[i]);
  const double mu = h * h * ratio;
  return mu / (1.0 + mu);
}

void ChebyshevAcceleration::begin(const SolverInput& in, const SolverSettings& settings) {
  const double rho = settings.params.number(settings::kChebyshevRho);
  if (rho > 0.0) rho_ = rho;
  else {
    rho_cache_.ensure(in.revision, LinearSolver::kFused, in.h,
                      [&] { rho_ = localGlobalRhoBound(in.model, in.h); });
  }
  gamma_ = settings.params.number(settings::kChebyshevGamma);
  delay_ = settings.params.integer(settings::kChebyshevDelay);
  threads_ = resolveThreads(settings.threads);
  omega_ = 1.0;
  since_restart_ = 0;
}

bool ChebyshevAcceleration::extrapolate(const NodeBuffer& x_prev, const NodeBuffer& x,
                                        const NodeBuffer& x_hat, NodeBuffer& x_next) {
  ++since_restart_;
  if (since_restart_ < delay_) {
    omega_ = 1.0;
    return false;
  }
  omega_ = (since_restart_ == delay_) ? 2.0 / (2.0 - rho_ * rho_)
                                      : 4.0 / (4.0 - rho_ * rho_ * omega_);
  const BlockSplit split(x.size(), 4096);  // doubles per block (elementwise: any split will do)
  x_next.resize(x.size());
  parallelFor(threads_, split.blocks(), [&](int b) {
    for (std::size_t i = split.begin(b); i < split.end(b); ++i) {
      x_next[i] = omega_ * (gamma_ * (x_hat[i] - x[i]) + x[i] - x_prev[i]) + x_prev[i];
    }
  });
  return true;
}

}  // namespace cloth_sim
