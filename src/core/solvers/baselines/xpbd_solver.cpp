#include "cloth_sim/core/solvers/baselines/xpbd_solver.h"

#include <cmath>
#include <cstddef>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "cloth_sim/core/solvers/implicit_euler_problem.h"

namespace cloth_sim {
namespace {

/// Throws naming @p field when xpbd has no use for its value (it would silently do nothing).
void refuse(const std::string& field, const std::string& value, const std::string& why) {
  throw std::invalid_argument(field + " = " + value + " is not supported by xpbd (" + why + ")");
}

/// The springs of @p springs grouped by colour, as PositionBasedDynamics groups its
/// constraints (SimulationModel::initConstraintGroups): each spring, in model order, joins the
/// first colour none of whose springs touches one of its particles, else opens a new one.
/// Returns the spring indices colour after colour (model order within a colour); @p colours
/// gets their number.
std::vector<int> colourOrder(const Springs& springs, int particles, int& colours) {
  std::vector<std::vector<int>> groups;
  std::vector<std::vector<char>> used;  // used[g][i]: particle i is in colour g
  for (std::size_t s = 0; s < springs.size(); ++s) {
    const int i = springs.first[s], j = springs.second[s];
    std::size_t g = 0;
    while (g < groups.size() && (used[g][i] || used[g][j])) ++g;
    if (g == groups.size()) {
      groups.emplace_back();
      used.emplace_back(static_cast<std::size_t>(particles), 0);
    }
    groups[g].push_back(static_cast<int>(s));
    used[g][i] = used[g][j] = 1;
  }
  std::vector<int> order;
  order.reserve(springs.size());
  for (const std::vector<int>& group : groups) order.insert(order.end(), group.begin(), group.end());
  colours = static_cast<int>(groups.size());
  return order;
}

}  // namespace

void XpbdSolver::prepare(const SolverInput& in) {
  const Model& model = in.model;
  const double h = in.h;
  const bool same_model = in.revision == revision_ &&
                          particles_ == static_cast<std::size_t>(model.particleCount()) &&
                          springs_ == model.springs.size();
  if (same_model && h == h_) return;
  if (!same_model) order_ = colourOrder(model.springs, model.particleCount(), colours_);
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
    if (in.pastDeadline(sweep)) {
      sweeps = sweep;
      cut = true;
      break;
    }
    for (const int s : order_) {  // colour by colour (colourOrder)
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
