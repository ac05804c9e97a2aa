#include "cloth_sim/core/solvers/local_global/local_global_problem.h"

#include <algorithm>
#include <utility>
#include <vector>

#include "cloth_sim/core/collision/contact_forces.h"

namespace cloth_sim {

double relativeChange(const NodeBuffer& next, const NodeBuffer& current, const NodeBuffer& start) {
  const double moved = (asVector(next) - asVector(start)).norm();
  return moved > 0.0 ? (asVector(next) - asVector(current)).norm() / moved : 0.0;
}

int LocalGlobalProblem::factorize(const SolverInput& in, LinearSolver backend, double h) {
  const Model& model = in.model;
  const Springs& springs = model.springs;
  const double h2 = h * h;
  dofs_ = FreeParticleMap::fromPins(model.particleCount(), in.pins);
  const FreeParticleMap& dofs = dofs_;
  const int nf = dofs.freeCount();

  const Eigen::SparseMatrix<double> a = globalStepMatrix(model, in.pins, dofs, h);
  system_.factor(a, backend);
  correction_.clear();  // node order and system changed

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
  springs_.partition(n);  // the local step's fixed blocks (threads)
  return nf > 0 ? 1 : 0;
}

int LocalGlobalProblem::begin(const SolverInput& in, const SolverSettings& settings,
                              const State& state) {
  const Model& model = in.model;
  threads_ = resolveThreads(settings.threads);
  problem_ = ImplicitStepProblem::build(model, in.pins, state, in.h, settings.integrator);
  h_ = problem_.implicit_h;
  int factorizations = 0;
  factor_cache_.ensure(in.revision, settings.linear_solver, h_, [&] {
    factorizations = factorize(in, settings.linear_solver, h_);
  });
  system_.setThreads(threads_);
  gravity_ = model.gravity;
  const int n = model.particleCount();
  const Points& y = problem_.inertial;

  const Points constant = globalStepConstant(model, in.pins, dofs_, h_, y);
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
  // Implicit midpoint solves for x_half and extrapolates x_{n+1} = 2 x_half - x_n: a contact
  // force found at the midpoint would be doubled by the extrapolation, so contacts are left to
  // Simulation's projection after the step (SolveResult::used_contacts false).
  contacts_ = problem_.midpoint ? nullptr : in.contacts;
  if (contacts_ != nullptr) contacts_->begin(model, y, compliance_, particle_node_, h_);
  return factorizations;
}

void LocalGlobalProblem::estimateCompliance(const Eigen::SparseMatrix<double>& a) {
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

void LocalGlobalProblem::buildNodeMatrix(const Eigen::SparseMatrix<double>& a) {
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

double LocalGlobalProblem::objectiveAndGradient(const NodeBuffer& x, NodeBuffer& gradient) {
  rhs_work_ = rhs_constant_;
  const double spring_energy = localStep3(springs_, x.data(), rhs_work_.data(), threads_);
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

double LocalGlobalProblem::objectiveWith(const NodeBuffer& x, double spring_energy) const {
  const double h2 = h_ * h_;
  return inertiaAndGravity(x.data(), inertial_.data(), node_mass_.data(),
                           static_cast<int>(node_mass_.size()), gravity_, h2, threads_) +
         h2 * (spring_energy + constant_energy_ + pinEnergy(x));
}

double LocalGlobalProblem::pinEnergy(const NodeBuffer& x) const {
  double e = 0.0;
  for (const Pin& pin : problem_.pins->pins()) {
    if (pin.isHard()) continue;
    const double* xp = &x[kNodeStride * particle_node_[pin.vertex]];
    e += 0.5 * pin.stiffness * (Vec3(xp[0], xp[1], xp[2]) - pin.target).squaredNorm();
  }
  return e;
}

double LocalGlobalProblem::iterate(const NodeBuffer& x, NodeBuffer& x_next) {
  copyNodes(rhs_constant_, x_next, threads_);
  if (contacts_ != nullptr && !contacts_->empty()) {
    // Forces from the current iterate first, so the last global solve and the spheres'
    // reactions use the same forces (exact momentum balance).
    contacts_->update(x);
    contacts_->addForces(x_next);
  }
  const double spring_energy = localStep3(springs_, x.data(), x_next.data(), threads_);
  system_.globalStep(x.data(), x_next.data());  // the free nodes, x, y and z at once
  const std::size_t pinned_begin = static_cast<std::size_t>(kNodeStride) * free_count_;
  std::copy(x.begin() + pinned_begin, x.end(), x_next.begin() + pinned_begin);
  return objectiveWith(x, spring_energy);
}

double LocalGlobalProblem::objectiveAt(const NodeBuffer& x) const {
  return objectiveWith(x, springEnergy3(springs_, x.data(), threads_));
}

NodeBuffer LocalGlobalProblem::initialGuess(const SolverSettings& settings) const {
  if (!settings.warm_start || correction_.size() != inertial_.size()) return inertial_;
  NodeBuffer guess(inertial_.size());
  asVector(guess) = asVector(inertial_) + asVector(correction_);
  // Only when it is the better start: after a jolt the last correction can point the wrong way.
  return objectiveAt(guess) < objectiveAt(inertial_) ? guess : inertial_;
}

void LocalGlobalProblem::finishStep(const NodeBuffer& x, State& state) {
  correction_.resize(x.size());
  asVector(correction_) = asVector(x) - asVector(inertial_);
  Points positions;
  toParticles(x, positions);
  state = problem_.finish(positions, state.time);
}

void LocalGlobalProblem::toParticles(const NodeBuffer& x, Points& out) const {
  out.resize(3, static_cast<Eigen::Index>(node_particle_.size()));
  for (std::size_t k = 0; k < node_particle_.size(); ++k)
    for (int c = 0; c < 3; ++c) out(c, node_particle_[k]) = x[kNodeStride * k + c];
}

}  // namespace cloth_sim
