#include "cloth_sim/core/local_global_solver.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "cloth_sim/core/contact_forces.h"
#include "cloth_sim/core/spring_kernels.h"

namespace cloth_sim {

void LocalGlobalSolver::factorize(const SolverInput& in) {
  const Model& model = in.model;
  const Springs& springs = model.springs;
  const double h2 = model.time_step * model.time_step;
  dofs_ = DofMap::fromPins(model.particleCount(), in.pins);
  const int nf = dofs_.freeCount();

  // A = M + h^2 L over the free particles; a spring to a hard-pinned particle keeps only its
  // diagonal term (its coupling moves to the right-hand side, see beginStep).
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(nf + 3 * springs.size() + in.pins.size());
  for (int f = 0; f < nf; ++f) entries.emplace_back(f, f, model.mass[dofs_.free_particles[f]]);
  for (const Pin& pin : in.pins.pins()) {
    if (!pin.isHard()) {
      const int f = dofs_.reduced_index[pin.vertex];
      entries.emplace_back(f, f, h2 * pin.stiffness);
    }
  }
  for (std::size_t s = 0; s < springs.size(); ++s) {
    const int i = dofs_.reduced_index[springs.first[s]], j = dofs_.reduced_index[springs.second[s]];
    const double k = h2 * springs.stiffness[s];
    if (i >= 0) entries.emplace_back(i, i, k);
    if (j >= 0) entries.emplace_back(j, j, k);
    if (i >= 0 && j >= 0) {
      entries.emplace_back(i, j, -k);
      entries.emplace_back(j, i, -k);
    }
  }
  Eigen::SparseMatrix<double> system(nf, nf);
  system.setFromTriplets(entries.begin(), entries.end());
  if (nf > 0) {
    factor_.compute(system);
    ++factorizations_;
    // Contact compliance estimate kappa / A_ii, kappa = A_jj (A^-1)_jj measured on the particle
    // with the largest diagonal (PROTOTYPE).
    int j = 0;
    for (int f = 0; f < nf; ++f) if (system.coeff(f, f) > system.coeff(j, j)) j = f;
    Eigen::VectorXd e = Eigen::VectorXd::Zero(nf);
    e[j] = 1.0;
    const double kappa = factor_.solve(e)[j] * system.coeff(j, j);
    compliance_ = Eigen::VectorXd::Zero(model.particleCount());
    for (int f = 0; f < nf; ++f) compliance_[dofs_.free_particles[f]] = kappa / system.coeff(f, f);
  }
  reduced_rhs_.resize(nf, 3);
  reduced_x_.resize(nf, 3);
  prepared_revision_ = in.revision;
  prepared_ = true;
}

void LocalGlobalSolver::beginStep(const SolverInput& in, const State& state) {
  if (!prepared_ || prepared_revision_ != in.revision) factorize(in);
  const Model& model = in.model;
  problem_ = ImplicitStepProblem::build(model, in.pins, state);
  const double h2 = problem_.h * problem_.h;
  const Points& y = problem_.inertial;
  contacts_ = in.contacts;
  if (contacts_ != nullptr) contacts_->begin(model, state.positions, y, compliance_);

  rhs_constant_ = (y + h2 * model.gravity.replicate(1, y.cols())) * model.mass.asDiagonal();
  for (const Pin& pin : in.pins.pins()) {
    if (!pin.isHard()) rhs_constant_.col(pin.vertex) += h2 * pin.stiffness * pin.target;
  }
  const Springs& springs = model.springs;
  for (std::size_t s = 0; s < springs.size(); ++s) {
    const int i = springs.first[s], j = springs.second[s];
    const bool free_i = dofs_.isFree(i), free_j = dofs_.isFree(j);
    if (free_i == free_j) continue;
    // Boundary spring: the pinned end's position is known; move its coupling to the rhs.
    const double k = h2 * springs.stiffness[s];
    if (free_i) rhs_constant_.col(i) += k * y.col(j);
    else rhs_constant_.col(j) += k * y.col(i);
  }
}

double LocalGlobalSolver::iterate(const Points& x, Points& x_next) {
  const Springs& springs = problem_.model->springs;
  const double h2 = problem_.h * problem_.h;
  rhs_ = rhs_constant_;
  if (contacts_ != nullptr) {
    // Update the forces from the current iterate first, so the last global solve and the
    // spheres' reactions use the same forces (exact momentum balance).
    contacts_->update(x);
    contacts_->addForces(rhs_);
  }
  double spring_energy = 0.0;
  const std::size_t m = springs.size();
  for (std::size_t s = 0; s < m; ++s) {
    // Local step (fused with the J d product): d_s = r_s (x_i - x_j)/|x_i - x_j|.
    const int i = springs.first[s], j = springs.second[s];
    const Vec3 d = x.col(i) - x.col(j);
    const double len = d.norm();
    const double stretch = len - springs.rest_length[s];
    spring_energy += 0.5 * springs.stiffness[s] * stretch * stretch;
    const Vec3 push = (h2 * springs.stiffness[s] * springs.rest_length[s]) * safeDirection(d);
    rhs_.col(i) += push;
    rhs_.col(j) -= push;
  }
  // Global step: one scalar factor, three right-hand sides.
  const int nf = dofs_.freeCount();
  for (int f = 0; f < nf; ++f) reduced_rhs_.row(f) = rhs_.col(dofs_.free_particles[f]).transpose();
  if (nf > 0) reduced_x_ = factor_.solve(reduced_rhs_);
  x_next = x;
  for (int f = 0; f < nf; ++f) x_next.col(dofs_.free_particles[f]) = reduced_x_.row(f).transpose();
  return problem_.objective(x, spring_energy);
}

namespace {
double relativeChange(const Points& next, const Points& current, const Points& start) {
  const double moved = (next - start).norm();
  return moved > 0.0 ? (next - current).norm() / moved : 0.0;
}
}  // namespace

SolveResult LocalGlobalSolver::step(const SolverInput& in, const SolverSettings& settings,
                                    State& state) {
  beginStep(in, state);
  clearTrace();
  Points x = problem_.inertial, x_next;
  SolveResult result;
  for (int k = 0; k < settings.max_iterations; ++k) {
    recordTrace(iterate(x, x_next));
    result.iterations = k + 1;
    result.convergence = relativeChange(x_next, x, problem_.inertial);
    x.swap(x_next);
    if (settings.tolerance > 0.0 && result.convergence < settings.tolerance) {
      result.converged = true;
      break;
    }
  }
  if (tracing()) recordTrace(objectiveAt(x));
  state = problem_.finish(x, state.time);
  result.used_contacts = solvesContacts();
  return result;
}

double ChebyshevSolver::calibrateRho(const SolverSettings& settings) {
  // Plain local/global contracts the error by about rho per iteration once the fast modes are
  // gone; measure it as the geometric mean of the last update-norm ratios.
  constexpr int kIterations = 30, kAveraged = 5;
  Points x = problem_.inertial, x_next;
  std::vector<double> updates;
  for (int k = 0; k < std::max(kIterations, settings.max_iterations); ++k) {
    iterate(x, x_next);
    updates.push_back((x_next - x).norm());
    x.swap(x_next);
  }
  const std::size_t last = updates.size() - 1;
  if (updates[last - kAveraged] <= 0.0 || updates[last] <= 0.0) return 0.0;
  const double rho = std::pow(updates[last] / updates[last - kAveraged], 1.0 / kAveraged);
  return std::clamp(rho, 0.0, 0.9999);
}

SolveResult ChebyshevSolver::step(const SolverInput& in, const SolverSettings& settings,
                                  State& state) {
  beginStep(in, state);
  if (settings.chebyshev_rho > 0.0) {
    rho_ = settings.chebyshev_rho;
  } else if (!calibrated_ || calibrated_revision_ != in.revision) {
    rho_ = calibrateRho(settings);
    calibrated_ = true;
    calibrated_revision_ = in.revision;
  }
  const double gamma = settings.chebyshev_gamma;
  const int delay = settings.chebyshev_delay;
  const Points& start = problem_.inertial;

  Points x = start, x_prev = start, x_hat, x_hat_prev, x_next;
  double g_prev = std::numeric_limits<double>::infinity();
  double omega = 1.0;
  int since_restart = 0, solves = 0;
  bool accelerated = false;  // whether x came from an accelerated update
  SolveResult result;
  clearTrace();
  while (solves < settings.max_iterations) {
    double g = iterate(x, x_hat);
    ++solves;
    if (accelerated && g > g_prev) {
      // Safeguard: the accelerated iterate raised g. Fall back to the plain iterate from
      // x_prev (g(x_hat_prev) <= g_prev) and restart the Chebyshev sequence.
      x = x_hat_prev;
      since_restart = 0;
      accelerated = false;
      if (solves >= settings.max_iterations) break;
      g = iterate(x, x_hat);
      ++solves;
    }
    recordTrace(g);
    ++since_restart;
    if (since_restart < delay) {
      omega = 1.0;
      x_next = x_hat;
      accelerated = false;
    } else {
      omega = (since_restart == delay) ? 2.0 / (2.0 - rho_ * rho_)
                                       : 4.0 / (4.0 - rho_ * rho_ * omega);
      x_next = omega * (gamma * (x_hat - x) + x - x_prev) + x_prev;
      accelerated = true;
    }
    result.iterations = solves;
    result.convergence = relativeChange(x_next, x, start);
    x_prev.swap(x);
    x_hat_prev.swap(x_hat);
    g_prev = g;
    x.swap(x_next);
    if (settings.tolerance > 0.0 && result.convergence < settings.tolerance) {
      result.converged = true;
      break;
    }
  }
  result.iterations = solves;
  // Never worse than plain local/global: the last accelerated iterate must beat the plain
  // iterate it was built from (two spring passes, no solve).
  if (accelerated && objectiveAt(x) > objectiveAt(x_hat_prev)) x = x_hat_prev;
  if (tracing()) recordTrace(objectiveAt(x));
  state = problem_.finish(x, state.time);
  result.used_contacts = solvesContacts();
  return result;
}

}  // namespace cloth_sim
