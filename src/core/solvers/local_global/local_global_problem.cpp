#include "cloth_sim/core/solvers/local_global/local_global_problem.h"

#include <algorithm>
#include <cmath>
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
  f_->dofs = FreeParticleMap::fromPins(model.particleCount(), in.pins);
  const FreeParticleMap& dofs = f_->dofs;
  const int nf = dofs.freeCount();

  const Eigen::SparseMatrix<double> a = globalStepMatrix(model, in.pins, dofs, h);
  f_->system.factor(a, backend);
  f_->system.setThreads(threads_);
  correction_.clear();  // node order and system changed

  // Node order: free particles in the system's order, then the hard-pinned ones.
  f_->free_count = nf;
  const int n = model.particleCount();
  f_->node_particle.clear();
  for (int k = 0; k < nf; ++k) f_->node_particle.push_back(dofs.free_particles[f_->system.order()[k]]);
  for (int p = 0; p < n; ++p) {
    if (!dofs.isFree(p)) f_->node_particle.push_back(p);
  }
  f_->particle_node.assign(n, 0);
  f_->node_mass.resize(n);
  for (int k = 0; k < n; ++k) {
    f_->particle_node[f_->node_particle[k]] = k;
    f_->node_mass[k] = model.mass[f_->node_particle[k]];
  }
  estimateCompliance(a);
  buildNodeMatrix(a);

  f_->springs = SpringTable{};
  f_->pinned_springs = SpringTable{};
  for (std::size_t s = 0; s < springs.size(); ++s) {
    const int a = f_->particle_node[springs.first[s]], b = f_->particle_node[springs.second[s]];
    const double k = springs.stiffness[s], r = springs.rest_length[s];
    if (a >= nf && b >= nf) {
      f_->pinned_springs.add(a, b, 0.0, k, r);
      continue;
    }
    f_->springs.add(a, b, h2 * k * r, k, r);
  }
  f_->springs.sortByNode();
  f_->springs.partition(n);  // the local step's fixed blocks (threads)
  return nf > 0 ? 1 : 0;
}

int LocalGlobalProblem::useFactor(const SolverInput& in, LinearSolver backend, double h) {
  const auto same = [&](const std::unique_ptr<Factored>& f) {
    return f->revision == in.revision && f->backend == backend && f->implicit_h == h;
  };
  const auto found = std::find_if(factors_.begin(), factors_.end(), same);
  if (found != factors_.end()) {
    std::rotate(found, found + 1, factors_.end());  // most recently used last
    if (f_ != factors_.back().get()) correction_.clear();  // a warm start is for its own h_i
    f_ = factors_.back().get();
    return 0;
  }
  // Another revision (a stiffness, a mass, the pin set) invalidates every kept factor.
  if (!factors_.empty() && factors_.back()->revision != in.revision) factors_.clear();
  if (factors_.size() >= kKeptFactors) factors_.erase(factors_.begin());
  factors_.push_back(std::make_unique<Factored>());
  f_ = factors_.back().get();
  f_->revision = in.revision;
  f_->backend = backend;
  f_->implicit_h = h;
  try {
    return factorize(in, backend, h);
  } catch (...) {
    factors_.pop_back();  // not built: never found again
    f_ = nullptr;
    throw;
  }
}

int LocalGlobalProblem::begin(const SolverInput& in, const SolverSettings& settings,
                              const State& state) {
  const Model& model = in.model;
  threads_ = resolveThreads(settings.threads);
  problem_ = ImplicitStepProblem::build(model, in.pins, state, in.h, settings.integrator);
  h_ = problem_.implicit_h;
  iteration_tolerance_ = in.iteration_tolerance;
  deadline_ = in.deadline;
  min_iterations_at_deadline_ = in.min_iterations_at_deadline;
  const int factorizations = useFactor(in, settings.linear_solver, h_);
  // Every kept factor solves on this step's threads, the ones made before too (the count may
  // change between steps; the results do not depend on it).
  for (const std::unique_ptr<Factored>& f : factors_) f->system.setThreads(threads_);
  gravity_ = model.gravity;
  const int n = model.particleCount();
  const Points& carried = pending_correction_.correction;
  if (carried.cols() == n && pending_correction_.implicit_h == h_) {  // restored, in node order
    correction_.assign(static_cast<std::size_t>(kNodeStride) * n, 0.0);
    for (int k = 0; k < n; ++k)
      for (int c = 0; c < 3; ++c) correction_[kNodeStride * k + c] = carried(c, f_->node_particle[k]);
  }
  pending_correction_ = SolverCarry();
  const Points& y = problem_.inertial;

  const Points constant = globalStepConstant(model, in.pins, f_->dofs, h_, y);
  inertial_.assign(static_cast<std::size_t>(kNodeStride) * n, 0.0);
  rhs_constant_.assign(inertial_.size(), 0.0);
  for (int k = 0; k < n; ++k) {
    const int p = f_->node_particle[k];
    for (int c = 0; c < 3; ++c) {
      inertial_[kNodeStride * k + c] = y(c, p);
      rhs_constant_[kNodeStride * k + c] = constant(c, p);
    }
  }
  constant_energy_ = springEnergy3(f_->pinned_springs, inertial_.data());
  // Implicit midpoint solves for x_half and extrapolates x_{n+1} = 2 x_half - x_n: a contact
  // force found at the midpoint would be doubled by the extrapolation, so contacts are left to
  // Simulation's projection after the step (SolveResult::used_contacts false).
  contacts_ = problem_.midpoint ? nullptr : in.contacts;
  if (contacts_ != nullptr) contacts_->begin(model, y, f_->compliance, f_->particle_node, h_);
  return factorizations;
}

void LocalGlobalProblem::estimateCompliance(const Eigen::SparseMatrix<double>& a) {
  // (A^-1)_ii ~ kappa / A_ii, kappa = A_jj (A^-1)_jj measured with one solve on the particle j
  // with the largest diagonal: exact for a diagonal A, and on a uniform sheet kappa is nearly
  // the same everywhere. Contacts only need the right order of magnitude (their update is a
  // relaxed projected Jacobi step).
  f_->compliance = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(f_->node_particle.size()));
  if (f_->free_count == 0) return;
  const Eigen::VectorXd diagonal = a.diagonal();
  Eigen::Index j = 0;
  diagonal.maxCoeff(&j);
  const std::size_t node = f_->particle_node[f_->dofs.free_particles[j]];
  NodeBuffer unit(static_cast<std::size_t>(kNodeStride) * f_->free_count, 0.0);
  unit[kNodeStride * node] = 1.0;
  f_->system.solveInPlace(unit.data());
  const double kappa = unit[kNodeStride * node] * diagonal[j];
  for (int f = 0; f < f_->free_count; ++f) f_->compliance[f_->dofs.free_particles[f]] = kappa / diagonal[f];
}

void LocalGlobalProblem::buildNodeMatrix(const Eigen::SparseMatrix<double>& a) {
  // Row k of the node matrix is free index order()[k]; A is symmetric, so that row is column
  // order()[k] of the column-major a.
  const std::vector<int>& order = f_->system.order();
  const int nf = static_cast<int>(order.size());
  NodeMatrix& m = f_->node_matrix;
  m.row_begin.assign(1, 0);
  m.column.clear();
  m.value.clear();
  std::vector<std::pair<int, double>> row;
  for (int k = 0; k < nf; ++k) {
    row.clear();
    for (Eigen::SparseMatrix<double>::InnerIterator it(a, order[k]); it; ++it)
      row.emplace_back(f_->particle_node[f_->dofs.free_particles[it.row()]], it.value());
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
  const double spring_energy = localStep3(f_->springs, x.data(), rhs_work_.data(), threads_);
  gradient.assign(x.size(), 0.0);
  const NodeMatrix& m = f_->node_matrix;
  for (int k = 0; k < f_->free_count; ++k) {
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
  return inertiaAndGravity(x.data(), inertial_.data(), f_->node_mass.data(),
                           static_cast<int>(f_->node_mass.size()), gravity_, h2, threads_) +
         h2 * (spring_energy + constant_energy_ + pinEnergy(x));
}

double LocalGlobalProblem::pinEnergy(const NodeBuffer& x) const {
  double e = 0.0;
  for (const Pin& pin : problem_.pins->pins()) {
    if (pin.isHard()) continue;
    const double* xp = &x[kNodeStride * f_->particle_node[pin.vertex]];
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
  const double spring_energy = localStep3(f_->springs, x.data(), x_next.data(), threads_);
  f_->system.globalStep(x.data(), x_next.data());  // the free nodes, x, y and z at once
  const std::size_t pinned_begin = static_cast<std::size_t>(kNodeStride) * f_->free_count;
  std::copy(x.begin() + pinned_begin, x.end(), x_next.begin() + pinned_begin);
  return objectiveWith(x, spring_energy);
}

double LocalGlobalProblem::rmsDistance(const NodeBuffer& a, const NodeBuffer& b) const {
  if (f_->free_count == 0) return 0.0;
  const Eigen::Index n = static_cast<Eigen::Index>(kNodeStride) * f_->free_count;
  return (asVector(a).head(n) - asVector(b).head(n)).norm() / std::sqrt(double(f_->free_count));
}

double LocalGlobalProblem::objectiveAt(const NodeBuffer& x) const {
  return objectiveWith(x, springEnergy3(f_->springs, x.data(), threads_));
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

SolverCarry LocalGlobalProblem::warmStart() const {
  SolverCarry out;
  if (!correction_.empty() && f_ != nullptr && correction_.size() == kNodeStride * f_->node_particle.size()) {
    toParticles(correction_, out.correction);
    out.implicit_h = h_;
  }
  return out;
}

void LocalGlobalProblem::toParticles(const NodeBuffer& x, Points& out) const {
  out.resize(3, static_cast<Eigen::Index>(f_->node_particle.size()));
  for (std::size_t k = 0; k < f_->node_particle.size(); ++k)
    for (int c = 0; c < 3; ++c) out(c, f_->node_particle[k]) = x[kNodeStride * k + c];
}

}  // namespace cloth_sim
