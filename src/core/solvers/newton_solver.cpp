#include "cloth_sim/core/solvers/newton_solver.h"

#include <cmath>
#include <limits>

#include "cloth_sim/core/solvers/implicit_euler_problem.h"
#include "cloth_sim/core/model/spring_kernels.h"

namespace cloth_sim {

void NewtonSolver::prepare(const SolverInput& in, LinearSolver backend) {
  const Model& model = in.model;
  dofs_ = FreeParticleMap::fromPins(model.particleCount(), in.pins);
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
  backend_ = backend;
  if (backend_ == LinearSolver::kEigen) eigen_.analyzePattern(pattern_.matrix());
  else if (dofs_.freeCount() > 0) cholmod_.analyze(pattern_.matrix());
}

void NewtonSolver::assembleHessian(const Model& model, const PinSet& pins, const Points& x,
                                   double h, bool clamp_psd) {
  const double h2 = h * h;
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
                                                         springs.stiffness[s], clamp_psd);
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

bool NewtonSolver::factorize() {
  ++factorizations_;
  if (backend_ == LinearSolver::kEigen) {
    eigen_.factorize(pattern_.matrix());
    return eigen_.info() == Eigen::Success;
  }
  return cholmod_.factorize(pattern_.matrix());
}

SolveResult NewtonSolver::step(const SolverInput& in, const SolverSettings& settings,
                               State& state) {
  const ImplicitStepProblem problem =
      ImplicitStepProblem::build(in.model, in.pins, state, in.h, settings.integrator);
  Points x = problem.inertial;
  const SolveResult result = minimize(in, settings, problem, x);
  state = problem.finish(x, state.time);
  return result;
}

SolveResult NewtonSolver::minimize(const SolverInput& in, const SolverSettings& settings,
                                   const ImplicitStepProblem& problem, Points& x) {
  pattern_cache_.ensure(in.revision, settings.linear_solver,
                        [&] { prepare(in, settings.linear_solver); });
  const double tolerance = settings.tolerance > 0.0 ? settings.tolerance : 1e-12;
  const int nf = dofs_.freeCount();
  auto free_norm = [&](const Points& grad) {
    double sum = 0.0;
    for (int f = 0; f < nf; ++f) sum += grad.col(dofs_.free_particles[f]).squaredNorm();
    return std::sqrt(sum);
  };

  double g = problem.objective(x);
  Points grad, trial, trial_grad;
  Eigen::VectorXd rhs(3 * nf), dx(3 * nf);
  bool near = false;  // last step was full and small: try the exact Hessian
  SolveResult result;
  problem.gradient(x, grad);
  for (int it = 0; it < settings.max_iterations; ++it) {
    for (int f = 0; f < nf; ++f) rhs.segment<3>(3 * f) = -grad.col(dofs_.free_particles[f]);
    if (rhs.squaredNorm() == 0.0) {
      result.converged = true;
      break;
    }
    bool factored = false;
    if (near) {
      assembleHessian(in.model, in.pins, x, problem.implicit_h, /*clamp_psd=*/false);
      factored = factorize();
    }
    const bool exact = factored;
    if (!factored) {
      assembleHessian(in.model, in.pins, x, problem.implicit_h, /*clamp_psd=*/true);
      if (!factorize()) break;  // cannot happen for H >= M > 0 short of non-finite input
    }
    if (backend_ == LinearSolver::kEigen) {
      dx = eigen_.solve(rhs);
    } else {
      dx = rhs;
      cholmod_.solveInPlace(dx.data(), 1);
    }
    auto take = [&](double alpha) {
      trial = x;
      for (int f = 0; f < nf; ++f) trial.col(dofs_.free_particles[f]) += alpha * dx.segment<3>(3 * f);
    };
    result.iterations = it + 1;
    // The full Newton step measures the distance to the minimiser whatever the line search
    // does; below tolerance, take it and stop.
    const double moved = (x - problem.inertial).norm();
    const double full_step = dx.norm() / std::max(moved, std::numeric_limits<double>::min());
    // Near the solution the full Newton step is the distance to it (quadratic convergence).
    result.iteration_error = dx.norm() / std::sqrt(double(nf));
    const bool close_enough =
        in.iteration_tolerance > 0.0 && result.iteration_error <= in.iteration_tolerance;
    if (full_step < tolerance || close_enough) {
      take(1.0);
      x.swap(trial);
      result.convergence = full_step;
      result.converged = true;
      break;
    }
    const double slope = -rhs.dot(dx);  // grad . dx < 0
    double alpha = 1.0, g_trial = std::numeric_limits<double>::infinity();
    if (-slope > 1e-13 * std::abs(g)) {
      for (; alpha > 1e-12; alpha *= 0.5) {
        take(alpha);
        g_trial = problem.objective(trial);
        if (g_trial <= g + 1e-4 * alpha * slope) break;
      }
    }
    if (alpha > 1e-12 && g_trial <= g) {
      problem.gradient(trial, grad);
    } else {
      // Round-off regime (the predicted decrease is below what g resolves, or no step lowered
      // it): g cannot tell better from worse, |grad g| still can. Backtrack on it instead.
      const double grad_norm = free_norm(grad);
      bool lowered = false;
      for (alpha = 1.0; alpha > 1e-3; alpha *= 0.5) {
        take(alpha);
        problem.gradient(trial, trial_grad);
        if (free_norm(trial_grad) < grad_norm) {
          lowered = true;
          break;
        }
      }
      if (!lowered) {
        result.converged = true;  // no step lowers g or |grad g|: x is the minimiser
        break;
      }
      g_trial = problem.objective(trial);
      grad.swap(trial_grad);
    }
    x.swap(trial);
    g = g_trial;
    result.convergence = alpha * dx.norm() / std::max((x - problem.inertial).norm(),
                                                      std::numeric_limits<double>::min());
    near = exact || (alpha == 1.0 && full_step < 1e-2);
    if (it + 1 < settings.max_iterations && in.pastDeadline(it + 1)) {
      result.cut = true;
      break;
    }
  }
  return result;
}

}  // namespace cloth_sim
