#include "cloth_sim/core/solvers/baselines/xpbd_solver.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "cloth_sim/core/solvers/implicit_euler_problem.h"

namespace cloth_sim {
namespace {

/// Throws naming @p field when xpbd has no use for its value (it would silently do nothing).
void refuse(const std::string& field, const std::string& value, const std::string& why) {
  throw std::invalid_argument(field + " = " + value + " is not supported by xpbd (" + why + ")");
}

}  // namespace

void XpbdSolver::prepare(const SolverInput& in) {
  const Model& model = in.model;
  const double h = in.h;
  if (in.revision == revision_ && h == h_ && particles_ == static_cast<std::size_t>(model.particleCount()) &&
      springs_ == model.springs.size()) {
    return;
  }
  revision_ = in.revision;
  h_ = h;
  particles_ = static_cast<std::size_t>(model.particleCount());
  springs_ = model.springs.size();
  inverse_mass_.resize(particles_);
  for (std::size_t i = 0; i < particles_; ++i) inverse_mass_[i] = 1.0 / model.mass[i];
  // Hard pins: infinite mass, the particle is moved only by its target.
  for (const Pin& pin : in.pins.pins()) {
    if (pin.isHard()) inverse_mass_[pin.vertex] = 0.0;
  }
  alpha_tilde_.resize(springs_);
  for (std::size_t s = 0; s < springs_; ++s) {
    const double k = model.springs.stiffness[s];
    alpha_tilde_[s] = k > 0.0 ? 1.0 / (k * h * h) : -1.0;
  }
  lambda_.assign(springs_, 0.0);
}

void XpbdSolver::requireSettings(const SolverSettings& settings) const {
  requireIntegrator(*this, settings.integrator);
  requireErrorControl(*this, settings);
  if (settings.tolerance > 0.0) {
    std::ostringstream value;
    value << settings.tolerance;
    refuse("solver.tolerance", value.str(),
           "it runs exactly solver.iterations Gauss-Seidel sweeps per step; must be 0");
  }
  if (settings.warm_start) {
    refuse("solver.warm_start", "true", "its iterations start from the prediction x + h v; must be false");
  }
}

SolveResult XpbdSolver::step(const SolverInput& in, const SolverSettings& settings, State& state) {
  requireSettings(settings);
  prepare(in);
  state.has_previous = false;  // no implicit step's history
  const Model& model = in.model;
  const double h = in.h, decay = velocityDecay(model, h);
  start_ = state.positions;  // a member: no allocation per substep
  const Points& start = start_;
  Points& p = state.positions;
  const int n = model.particleCount();
  for (int i = 0; i < n; ++i) {
    if (inverse_mass_[i] == 0.0) continue;
    state.velocities.col(i) = decay * state.velocities.col(i) + h * model.gravity;
    p.col(i) += h * state.velocities.col(i);
  }
  for (const Pin& pin : in.pins.pins()) {
    if (pin.isHard()) p.col(pin.vertex) = pin.target;
  }

  const Springs& springs = model.springs;
  const int* first = springs.first.data();
  const int* second = springs.second.data();
  const double* rest = springs.rest_length.data();
  const double* w = inverse_mass_.data();
  double* x = p.data();
  std::fill(lambda_.begin(), lambda_.end(), 0.0);
  pin_lambda_.assign(in.pins.pins().size(), Vec3::Zero());
  std::vector<Vec3>& pin_lambda = pin_lambda_;
  int sweeps = settings.max_iterations;
  bool cut = false;
  for (int sweep = 0; sweep < sweeps; ++sweep) {
    if (sweep > 0 && in.pastDeadline()) {
      sweeps = sweep;
      cut = true;
      break;
    }
    for (std::size_t s = 0; s < springs_; ++s) {
      const double alpha = alpha_tilde_[s];
      const int i = first[s], j = second[s];
      const double wsum = w[i] + w[j];
      if (alpha < 0.0 || wsum == 0.0) continue;
      double* xi = x + 3 * i;
      double* xj = x + 3 * j;
      const double dx = xi[0] - xj[0], dy = xi[1] - xj[1], dz = xi[2] - xj[2];
      const double length = std::sqrt(dx * dx + dy * dy + dz * dz);
      if (!(length > 1e-12)) continue;  // no direction: leave it to the other constraints
      const double c = length - rest[s];
      const double dlambda = (-c - alpha * lambda_[s]) / (wsum + alpha);
      lambda_[s] += dlambda;
      const double scale = dlambda / length;  // dlambda n, n = d / |d|
      const double ai = w[i] * scale, aj = w[j] * scale;
      xi[0] += ai * dx, xi[1] += ai * dy, xi[2] += ai * dz;
      xj[0] -= aj * dx, xj[1] -= aj * dy, xj[2] -= aj * dz;
    }
    // Soft pins: the vector constraint x_p - t of compliance 1 / k_p (three independent rows).
    for (std::size_t k = 0; k < in.pins.pins().size(); ++k) {
      const Pin& pin = in.pins.pins()[k];
      if (pin.isHard() || w[pin.vertex] == 0.0) continue;
      const double alpha = 1.0 / (pin.stiffness * h * h);
      const Vec3 c = p.col(pin.vertex) - pin.target;
      const Vec3 dlambda = (-c - alpha * pin_lambda[k]) / (w[pin.vertex] + alpha);
      pin_lambda[k] += dlambda;
      p.col(pin.vertex) += w[pin.vertex] * dlambda;
    }
  }
  state.velocities = (p - start) / h;
  state.time += h;
  SolveResult result{sweeps, 0.0, false, false};
  result.cut = cut;
  return result;
}

}  // namespace cloth_sim
