#include "cloth_sim/core/newton_solver.h"

#include <cmath>
#include <limits>

#include "cloth_sim/core/implicit_euler.h"
#include "cloth_sim/core/spring_kernels.h"

namespace cloth_sim {

void NewtonSolver::prepare(const SolverInput& in) {
  const Model& model = in.model;
  dofs_ = DofMap::fromPins(model.particleCount(), in.pins);
  const Springs& springs = model.springs;
  std::vector<std::pair<int, int>> pairs;
  for (std::size_t s = 0; s < springs.size(); ++s) {
    const int i = dofs_.reduced_index[springs.first[s]], j = dofs_.reduced_index[springs.second[s]];
    if (i >= 0 && j >= 0) pairs.emplace_back(i, j);
  }
  pattern_ = BlockPattern(dofs_.freeCount(), 3, pairs);

  diagonal_slots_.resize(dofs_.freeCount());
  for (int f = 0; f < dofs_.freeCount(); ++f)
    for (int b = 0; b < 3; ++b) diagonal_slots_[f][b] = pattern_.columnStart(f, f, b);

  spring_slots_.assign(springs.size(), {});
  for (std::size_t s = 0; s < springs.size(); ++s) {
    const int i = dofs_.reduced_index[springs.first[s]], j = dofs_.reduced_index[springs.second[s]];
    auto& slots = spring_slots_[s];
    slots.fill(-1);
    if (i < 0 || j < 0) continue;
    for (int b = 0; b < 3; ++b) {
      slots[b] = pattern_.columnStart(i, i, b);
      slots[3 + b] = pattern_.columnStart(j, j, b);
      slots[6 + b] = pattern_.columnStart(i, j, b);
      slots[9 + b] = pattern_.columnStart(j, i, b);
    }
  }
  factor_.analyzePattern(pattern_.matrix());
  prepared_revision_ = in.revision;
  prepared_ = true;
}

void NewtonSolver::assembleHessian(const Model& model, const PinSet& pins, const Points& x) {
  const double h2 = model.time_step * model.time_step;
  double* values = pattern_.matrix().valuePtr();
  std::fill(values, values + pattern_.matrix().nonZeros(), 0.0);
  auto add_block = [values](const int* starts, const Eigen::Matrix3d& block, double sign) {
    for (int b = 0; b < 3; ++b)
      for (int a = 0; a < 3; ++a) values[starts[b] + a] += sign * block(a, b);
  };
  for (int f = 0; f < dofs_.freeCount(); ++f) {
    add_block(diagonal_slots_[f].data(),
              model.mass[dofs_.free_particles[f]] * Eigen::Matrix3d::Identity(), 1.0);
  }
  for (const Pin& pin : pins.pins()) {
    if (pin.isHard()) continue;
    add_block(diagonal_slots_[dofs_.reduced_index[pin.vertex]].data(),
              h2 * pin.stiffness * Eigen::Matrix3d::Identity(), 1.0);
  }
  const Springs& springs = model.springs;
  for (std::size_t s = 0; s < springs.size(); ++s) {
    const int pi = springs.first[s], pj = springs.second[s];
    const int i = dofs_.reduced_index[pi], j = dofs_.reduced_index[pj];
    if (i < 0 && j < 0) continue;
    const Eigen::Matrix3d hess = h2 * springHessianBlock(x.col(pi) - x.col(pj),
                                                         springs.rest_length[s],
                                                         springs.stiffness[s], /*clamp_psd=*/true);
    if (i >= 0 && j >= 0) {
      const int* slots = spring_slots_[s].data();
      add_block(slots, hess, 1.0);
      add_block(slots + 3, hess, 1.0);
      add_block(slots + 6, hess, -1.0);
      add_block(slots + 9, hess, -1.0);
    } else {
      add_block(diagonal_slots_[i >= 0 ? i : j].data(), hess, 1.0);
    }
  }
}

SolveResult NewtonSolver::step(const SolverInput& in, const SolverSettings& settings,
                               State& state) {
  if (!prepared_ || prepared_revision_ != in.revision) prepare(in);
  const ImplicitStepProblem problem = ImplicitStepProblem::build(in.model, in.pins, state);
  const double tolerance = settings.tolerance > 0.0 ? settings.tolerance : 1e-12;
  const int nf = dofs_.freeCount();

  Points x = problem.inertial;
  double g = problem.objective(x);
  Points grad, trial;
  Eigen::VectorXd rhs(3 * nf);
  SolveResult result;
  for (int it = 0; it < settings.max_iterations; ++it) {
    problem.gradient(x, grad);
    for (int f = 0; f < nf; ++f) rhs.segment<3>(3 * f) = -grad.col(dofs_.free_particles[f]);
    if (rhs.squaredNorm() == 0.0) {
      result.converged = true;
      break;
    }
    assembleHessian(in.model, in.pins, x);
    factor_.factorize(pattern_.matrix());
    ++factorizations_;
    if (factor_.info() != Eigen::Success) break;
    const Eigen::VectorXd dx = factor_.solve(rhs);
    const double slope = -rhs.dot(dx);  // grad . dx < 0
    double alpha = 1.0, g_trial = std::numeric_limits<double>::infinity();
    for (; alpha > 1e-12; alpha *= 0.5) {
      trial = x;
      for (int f = 0; f < nf; ++f) trial.col(dofs_.free_particles[f]) += alpha * dx.segment<3>(3 * f);
      g_trial = problem.objective(trial);
      if (g_trial <= g + 1e-4 * alpha * slope) break;
    }
    result.iterations = it + 1;
    if (!(g_trial <= g)) {  // no decrease left at machine precision: x is the minimiser
      result.converged = true;
      break;
    }
    x.swap(trial);
    g = g_trial;
    const double moved = (x - problem.inertial).norm();
    result.convergence = moved > 0.0 ? alpha * dx.norm() / moved : 0.0;
    if (result.convergence < tolerance) {
      result.converged = true;
      break;
    }
  }
  state = problem.finish(x, state.time);
  return result;
}

}  // namespace cloth_sim
