#include "cloth_sim/core/solvers/baselines/local_global_3n_solver.h"

#include <cmath>

#include "cloth_sim/core/solvers/local_global/global_system.h"
#include "cloth_sim/core/model/spring_kernels.h"

namespace cloth_sim {

void LocalGlobal3nSolver::factorize(const SolverInput& in, double h) {
  dofs_ = FreeParticleMap::fromPins(in.model.particleCount(), in.pins);
  const Eigen::SparseMatrix<double> scalar = globalStepMatrix(in.model, in.pins, dofs_, h);
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(3 * scalar.nonZeros());
  for (int col = 0; col < scalar.outerSize(); ++col) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(scalar, col); it; ++it) {
      for (int c = 0; c < 3; ++c) entries.emplace_back(3 * it.row() + c, 3 * col + c, it.value());
    }
  }
  const int n3 = 3 * dofs_.freeCount();
  Eigen::SparseMatrix<double> system(n3, n3);
  system.setFromTriplets(entries.begin(), entries.end());
  if (n3 > 0) {
    factor_.compute(system);
    ++factorizations_;
  }
  rhs_.resize(n3);
  solution_.resize(n3);
}

SolveResult LocalGlobal3nSolver::step(const SolverInput& in, const SolverSettings& settings,
                                      State& state) {
  const Model& model = in.model;
  const Springs& springs = model.springs;
  const ImplicitStepProblem problem =
      ImplicitStepProblem::build(model, in.pins, state, in.h, settings.integrator);
  const double h = problem.implicit_h, h2 = h * h;
  factor_cache_.ensure(in.revision, LinearSolver::kEigen, h, [&] { factorize(in, h); });
  const Points constant = globalStepConstant(model, in.pins, dofs_, h, problem.inertial);
  const int nf = dofs_.freeCount();

  Points x = problem.inertial, x_next = x, push_sum(3, x.cols());
  IterationError error;
  SolveResult result;
  for (int k = 0; k < settings.max_iterations; ++k) {
    // Local step and J d, per particle.
    push_sum.setZero();
    for (std::size_t s = 0; s < springs.size(); ++s) {
      const int i = springs.first[s], j = springs.second[s];
      const Vec3 d = (h2 * springs.stiffness[s] * springs.rest_length[s]) *
                     safeDirection(x.col(i) - x.col(j));
      push_sum.col(i) += d;
      push_sum.col(j) -= d;
    }
    // Global step: one 3N right-hand side, one 3N x 3N factor.
    for (int f = 0; f < nf; ++f) {
      const int p = dofs_.free_particles[f];
      rhs_.segment<3>(3 * f) = constant.col(p) + push_sum.col(p);
    }
    if (nf > 0) solution_ = factor_.solve(rhs_);
    for (int f = 0; f < nf; ++f) x_next.col(dofs_.free_particles[f]) = solution_.segment<3>(3 * f);
    result.iterations = k + 1;
    const double moved = (x_next - problem.inertial).norm();
    result.convergence = moved > 0.0 ? (x_next - x).norm() / moved : 0.0;
    const double change = nf > 0 ? (x_next - x).norm() / std::sqrt(double(nf)) : 0.0;
    x = x_next;
    if (in.iteration_tolerance > 0.0 && error.add(change) <= in.iteration_tolerance) {
      result.converged = true;
      break;
    }
    if (settings.tolerance > 0.0 && result.convergence < settings.tolerance) {
      result.converged = true;
      break;
    }
    if (k + 1 < settings.max_iterations && in.pastDeadline(k + 1)) {
      result.cut = true;
      break;
    }
  }
  if (in.iteration_tolerance > 0.0) result.iteration_error = error.estimate();
  state = problem.finish(x, state.time);
  return result;
}

}  // namespace cloth_sim
