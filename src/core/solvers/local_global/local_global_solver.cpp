#include "cloth_sim/core/solvers/local_global/local_global_solver.h"

#include <algorithm>
#include <limits>
#include <utility>
#include <vector>

#include "cloth_sim/core/collision/contact_forces.h"

namespace cloth_sim {
namespace {

Eigen::Map<Eigen::VectorXd> view(NodeBuffer& v) {
  return Eigen::Map<Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
}
Eigen::Map<const Eigen::VectorXd> view(const NodeBuffer& v) {
  return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
}

}  // namespace

double relativeChange(const NodeBuffer& next, const NodeBuffer& current, const NodeBuffer& start) {
  const double moved = (view(next) - view(start)).norm();
  return moved > 0.0 ? (view(next) - view(current)).norm() / moved : 0.0;
}

void LocalGlobalSolver::factorize(const SolverInput& in, LinearSolver backend) {
  const Model& model = in.model;
  const Springs& springs = model.springs;
  const double h2 = model.time_step * model.time_step;
  dofs_ = FreeParticleMap::fromPins(model.particleCount(), in.pins);
  const FreeParticleMap& dofs = dofs_;
  const int nf = dofs.freeCount();

  const Eigen::SparseMatrix<double> a = globalStepMatrix(model, in.pins, dofs);
  system_.factor(a, backend);
  correction_.clear();  // node order and system changed
  if (nf > 0) ++factorizations_;

  // Node order: free particles in the system's order, then the hard-pinned ones.
  free_count_ = nf;
  const int n = model.particleCount();
  node_particle_.clear();
  for (int k = 0; k < nf; ++k) node_particle_.push_back(dofs.free_particles[system_.order()[k]]);
  for (int p = 0; p < n; ++p) {
    if (!dofs.isFree(p)) node_particle_.push_back(p);
  }
  particle_node_.assign(n, 0);
  node_mass_.resize(n);
  for (int k = 0; k < n; ++k) {
    particle_node_[node_particle_[k]] = k;
    node_mass_[k] = model.mass[node_particle_[k]];
  }
  estimateCompliance(a);
  buildNodeMatrix(a);

  springs_ = SpringTable{};
  pinned_springs_ = SpringTable{};
  for (std::size_t s = 0; s < springs.size(); ++s) {
    const int a = particle_node_[springs.first[s]], b = particle_node_[springs.second[s]];
    const double k = springs.stiffness[s], r = springs.rest_length[s];
    if (a >= nf && b >= nf) {
      pinned_springs_.add(a, b, 0.0, k, r);
      continue;
    }
    springs_.add(a, b, h2 * k * r, k, r);
  }
  springs_.sortByNode();
  prepared_revision_ = in.revision;
  prepared_ = true;
}

void LocalGlobalSolver::beginStep(const SolverInput& in, const SolverSettings& settings,
                                  const State& state) {
  if (!prepared_ || prepared_revision_ != in.revision ||
      system_.backend() != settings.linear_solver) {
    factorize(in, settings.linear_solver);
  }
  const Model& model = in.model;
  problem_ = ImplicitStepProblem::build(model, in.pins, state);
  h_ = problem_.h;
  gravity_ = model.gravity;
  const int n = model.particleCount();
  const Points& y = problem_.inertial;

  const Points constant = globalStepConstant(model, in.pins, dofs_, y);
  inertial_.assign(static_cast<std::size_t>(kNodeStride) * n, 0.0);
  rhs_constant_.assign(inertial_.size(), 0.0);
  for (int k = 0; k < n; ++k) {
    const int p = node_particle_[k];
    for (int c = 0; c < 3; ++c) {
      inertial_[kNodeStride * k + c] = y(c, p);
      rhs_constant_[kNodeStride * k + c] = constant(c, p);
    }
  }
  constant_energy_ = springEnergy3(pinned_springs_, inertial_.data());
  contacts_ = in.contacts;
  if (contacts_ != nullptr) contacts_->begin(model, state.positions, y, compliance_);
}

void LocalGlobalSolver::estimateCompliance(const Eigen::SparseMatrix<double>& a) {
  // (A^-1)_ii ~ kappa / A_ii, kappa = A_jj (A^-1)_jj measured with one solve on the particle j
  // with the largest diagonal: exact for a diagonal A, and on a uniform sheet kappa is nearly
  // the same everywhere. Contacts only need the right order of magnitude (their update is a
  // relaxed projected Jacobi step).
  compliance_ = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(node_particle_.size()));
  if (free_count_ == 0) return;
  const Eigen::VectorXd diagonal = a.diagonal();
  Eigen::Index j = 0;
  diagonal.maxCoeff(&j);
  const std::size_t node = particle_node_[dofs_.free_particles[j]];
  NodeBuffer unit(static_cast<std::size_t>(kNodeStride) * free_count_, 0.0);
  unit[kNodeStride * node] = 1.0;
  system_.solveInPlace(unit.data());
  const double kappa = unit[kNodeStride * node] * diagonal[j];
  for (int f = 0; f < free_count_; ++f) compliance_[dofs_.free_particles[f]] = kappa / diagonal[f];
}

void LocalGlobalSolver::addContactForces(const NodeBuffer& x, NodeBuffer& rhs) {
  const int n = static_cast<int>(node_particle_.size());
  toParticles(x, contact_x_);
  // Forces from the current iterate first, so the last global solve and the spheres'
  // reactions use the same forces (exact momentum balance).
  contacts_->update(contact_x_);
  contact_rhs_.setZero(3, n);
  contacts_->addForces(contact_rhs_);
  for (int k = 0; k < free_count_; ++k)
    for (int c = 0; c < 3; ++c) rhs[kNodeStride * k + c] += contact_rhs_(c, node_particle_[k]);
}

void LocalGlobalSolver::buildNodeMatrix(const Eigen::SparseMatrix<double>& a) {
  // Row k of the node matrix is free index order()[k]; A is symmetric, so that row is column
  // order()[k] of the column-major a.
  const std::vector<int>& order = system_.order();
  const int nf = static_cast<int>(order.size());
  NodeMatrix& m = node_matrix_;
  m.row_begin.assign(1, 0);
  m.column.clear();
  m.value.clear();
  std::vector<std::pair<int, double>> row;
  for (int k = 0; k < nf; ++k) {
    row.clear();
    for (Eigen::SparseMatrix<double>::InnerIterator it(a, order[k]); it; ++it)
      row.emplace_back(particle_node_[dofs_.free_particles[it.row()]], it.value());
    std::sort(row.begin(), row.end());  // walk x forwards
    for (const auto& [column, value] : row) {
      m.column.push_back(column);
      m.value.push_back(value);
    }
    m.row_begin.push_back(static_cast<int>(m.column.size()));
  }
}

double LocalGlobalSolver::objectiveAndGradient(const NodeBuffer& x, NodeBuffer& gradient) {
  rhs_work_ = rhs_constant_;
  const double spring_energy = localStep3(springs_, x.data(), rhs_work_.data());
  gradient.assign(x.size(), 0.0);
  const NodeMatrix& m = node_matrix_;
  for (int k = 0; k < free_count_; ++k) {
    double ax = 0.0, ay = 0.0, az = 0.0;
    for (int e = m.row_begin[k]; e < m.row_begin[k + 1]; ++e) {
      const double* xj = &x[kNodeStride * m.column[e]];
      ax += m.value[e] * xj[0];
      ay += m.value[e] * xj[1];
      az += m.value[e] * xj[2];
    }
    double* gk = &gradient[kNodeStride * k];
    const double* bk = &rhs_work_[kNodeStride * k];
    gk[0] = ax - bk[0];
    gk[1] = ay - bk[1];
    gk[2] = az - bk[2];
  }
  return objectiveWith(x, spring_energy);
}

double LocalGlobalSolver::objectiveWith(const NodeBuffer& x, double spring_energy) const {
  const double h2 = h_ * h_;
  return inertiaAndGravity(x.data(), inertial_.data(), node_mass_.data(),
                           static_cast<int>(node_mass_.size()), gravity_, h2) +
         h2 * (spring_energy + constant_energy_ + pinEnergy(x));
}

double LocalGlobalSolver::pinEnergy(const NodeBuffer& x) const {
  double e = 0.0;
  for (const Pin& pin : problem_.pins->pins()) {
    if (pin.isHard()) continue;
    const double* xp = &x[kNodeStride * particle_node_[pin.vertex]];
    e += 0.5 * pin.stiffness * (Vec3(xp[0], xp[1], xp[2]) - pin.target).squaredNorm();
  }
  return e;
}

double LocalGlobalSolver::iterate(const NodeBuffer& x, NodeBuffer& x_next) {
  x_next = rhs_constant_;
  if (contacts_ != nullptr && !contacts_->empty()) addContactForces(x, x_next);
  const double spring_energy = localStep3(springs_, x.data(), x_next.data());
  system_.solveInPlace(x_next.data());  // global step: the free nodes, x, y and z at once
  const std::size_t pinned_begin = static_cast<std::size_t>(kNodeStride) * free_count_;
  std::copy(x.begin() + pinned_begin, x.end(), x_next.begin() + pinned_begin);
  return objectiveWith(x, spring_energy);
}

double LocalGlobalSolver::objectiveAt(const NodeBuffer& x) const {
  return objectiveWith(x, springEnergy3(springs_, x.data()));
}

NodeBuffer LocalGlobalSolver::initialGuess(const SolverSettings& settings) const {
  if (!settings.warm_start || correction_.size() != inertial_.size()) return inertial_;
  NodeBuffer guess(inertial_.size());
  view(guess) = view(inertial_) + view(correction_);
  // Only when it is the better start: after a jolt the last correction can point the wrong way.
  return objectiveAt(guess) < objectiveAt(inertial_) ? guess : inertial_;
}

void LocalGlobalSolver::finishStep(const NodeBuffer& x, State& state) {
  correction_.resize(x.size());
  view(correction_) = view(x) - view(inertial_);
  Points positions;
  toParticles(x, positions);
  state = problem_.finish(positions, state.time);
}

void LocalGlobalSolver::toParticles(const NodeBuffer& x, Points& out) const {
  out.resize(3, static_cast<Eigen::Index>(node_particle_.size()));
  for (std::size_t k = 0; k < node_particle_.size(); ++k)
    for (int c = 0; c < 3; ++c) out(c, node_particle_[k]) = x[kNodeStride * k + c];
}

bool LocalGlobalSolver::observe(int k, const NodeBuffer& x) const {
  if (!observer_) return true;
  toParticles(x, observed_);
  return observer_(k, observed_);
}

SolveResult LocalGlobalSolver::step(const SolverInput& in, const SolverSettings& settings,
                                    State& state) {
  beginStep(in, settings, state);
  clearTrace();
  const NodeBuffer start = initialGuess(settings);
  NodeBuffer x = start, x_next(x.size());
  SolveResult result;
  for (int k = 0; k < settings.max_iterations; ++k) {
    recordTrace(iterate(x, x_next));
    result.iterations = k + 1;
    // Two norm passes: only when read (tolerance, an observer that may stop here, the last).
    if (settings.tolerance > 0.0 || observing() || k + 1 == settings.max_iterations)
      result.convergence = relativeChange(x_next, x, start);
    x.swap(x_next);
    if (!observe(k + 1, x)) break;
    if (settings.tolerance > 0.0 && result.convergence < settings.tolerance) {
      result.converged = true;
      break;
    }
  }
  if (tracing()) recordTrace(objectiveAt(x));
  finishStep(x, state);
  result.used_contacts = solvesContacts();
  return result;
}

double localGlobalRhoBound(const Model& model) {
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
  const double mu = model.time_step * model.time_step * ratio;
  return mu / (1.0 + mu);
}

SolveResult ChebyshevSolver::step(const SolverInput& in, const SolverSettings& settings,
                                  State& state) {
  beginStep(in, settings, state);
  if (settings.chebyshev_rho > 0.0) {
    rho_ = settings.chebyshev_rho;
  } else if (!rho_set_ || rho_revision_ != in.revision) {
    rho_ = localGlobalRhoBound(in.model);
    rho_set_ = true;
    rho_revision_ = in.revision;
  }
  const double gamma = settings.chebyshev_gamma;
  const int delay = settings.chebyshev_delay;
  const NodeBuffer start = initialGuess(settings);

  NodeBuffer x = start, x_prev = start, x_hat(x.size()), x_hat_prev(x.size()), x_next(x.size());
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
      if (solves >= settings.max_iterations) {
        observe(solves, x);  // the step ends on this plain iterate
        break;
      }
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
      view(x_next) = omega * (gamma * (view(x_hat) - view(x)) + view(x) - view(x_prev)) +
                     view(x_prev);
      accelerated = true;
    }
    result.iterations = solves;
    result.convergence = relativeChange(x_next, x, start);
    x_prev.swap(x);
    x_hat_prev.swap(x_hat);
    g_prev = g;
    x.swap(x_next);
    if (observing()) {  // what the step would return if it stopped here (see the end)
      if (accelerated && objectiveAt(x) > objectiveAt(x_hat_prev)) {
        if (!observe(solves, x_hat_prev)) {
          x = x_hat_prev;
          accelerated = false;
          break;
        }
      } else if (!observe(solves, x)) {
        accelerated = false;
        break;
      }
    }
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
  finishStep(x, state);
  result.used_contacts = solvesContacts();
  return result;
}

void AndersonSolver::resetHistory() {
  history_ = 0;
  next_column_ = 0;  // columns 0 .. history_ - 1 are the ones in use until the ring is full
  has_last_ = false;
}

void AndersonSolver::pushHistory(const NodeBuffer& f, const NodeBuffer& g_map, int window) {
  const Eigen::Index n = static_cast<Eigen::Index>(f.size());
  if (d_f_.rows() != n || d_f_.cols() != window) {
    d_f_.resize(n, window);
    d_g_.resize(n, window);
    gram_.setZero(window, window);
    history_ = 0;
    next_column_ = 0;
  }
  if (has_last_) {
    // The least-squares problem does not depend on the column order: overwrite the oldest.
    const int c = next_column_;
    d_f_.col(c) = view(f) - view(f_last_);
    d_g_.col(c) = view(g_map) - view(g_last_);
    history_ = std::min(history_ + 1, window);
    next_column_ = (c + 1) % window;
    for (int j = 0; j < history_; ++j) gram_(c, j) = gram_(j, c) = d_f_.col(c).dot(d_f_.col(j));
  }
  f_last_ = f;
  g_last_ = g_map;
  has_last_ = true;
}

void AndersonSolver::extrapolate(const NodeBuffer& f, const NodeBuffer& g_map,
                                 NodeBuffer& x) const {
  view(x) = view(g_map);
  if (history_ == 0) return;
  // Normal equations (dF^T dF) theta = dF^T F (dF^T dF kept up to date column by column), with
  // a tiny Tikhonov term against nearly collinear columns.
  Eigen::MatrixXd gram = gram_.topLeftCorner(history_, history_);
  const Eigen::VectorXd rhs = d_f_.leftCols(history_).transpose() * view(f);
  gram.diagonal().array() += 1e-12 * std::max(gram.diagonal().maxCoeff(), 1e-300);
  const Eigen::VectorXd theta = gram.ldlt().solve(rhs);
  if (!theta.allFinite()) return;
  view(x).noalias() -= d_g_.leftCols(history_) * theta;  // noalias: no n-sized temporary
}

SolveResult AndersonSolver::step(const SolverInput& in, const SolverSettings& settings,
                                 State& state) {
  beginStep(in, settings, state);
  const int window = settings.anderson_window;
  const NodeBuffer start = initialGuess(settings);
  NodeBuffer x = start, x_next(x.size()), g_map(x.size()), g_map_prev(x.size()), f(x.size());
  double g_prev = std::numeric_limits<double>::infinity();
  int solves = 0;
  bool accelerated = false;  // whether x came from an extrapolation
  resetHistory();
  SolveResult result;
  clearTrace();
  while (solves < settings.max_iterations) {
    double g = iterate(x, g_map);
    ++solves;
    if (accelerated && g > g_prev) {
      // Safeguard: the extrapolated x raised g. Back to the plain iterate G(x_prev), whose g
      // is <= g_prev, and forget the history.
      ++rejections_;
      x = g_map_prev;
      accelerated = false;
      resetHistory();
      if (solves >= settings.max_iterations) {
        observe(solves, x);  // the step ends on this plain iterate
        break;
      }
      g = iterate(x, g_map);
      ++solves;
    }
    recordTrace(g);
    view(f) = view(g_map) - view(x);
    pushHistory(f, g_map, window);
    extrapolate(f, g_map, x_next);
    accelerated = history_ > 0;
    result.iterations = solves;
    result.convergence = relativeChange(x_next, x, start);
    g_map_prev.swap(g_map);
    g_prev = g;
    x.swap(x_next);
    if (observing()) {  // what the step would return if it stopped here (see the end)
      const bool plain_better = accelerated && objectiveAt(x) > objectiveAt(g_map_prev);
      if (!observe(solves, plain_better ? g_map_prev : x)) {
        if (plain_better) x = g_map_prev;
        accelerated = false;
        break;
      }
    }
    if (settings.tolerance > 0.0 && result.convergence < settings.tolerance) {
      result.converged = true;
      break;
    }
  }
  result.iterations = solves;
  // Never worse than the plain iterate it was extrapolated from (two spring passes, no solve).
  if (accelerated && objectiveAt(x) > objectiveAt(g_map_prev)) x = g_map_prev;
  if (tracing()) recordTrace(objectiveAt(x));
  finishStep(x, state);
  result.used_contacts = solvesContacts();
  return result;
}

}  // namespace cloth_sim
