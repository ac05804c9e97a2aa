#include "cloth_sim/core/simulation/substep.h"

#include <algorithm>
#include <chrono>

#include "cloth_sim/core/collision/sphere_impacts.h"
#include "cloth_sim/core/solvers/implicit_euler_problem.h"

namespace cloth_sim {

void SubstepPipeline::run(const SubstepWorld& world, const PinSet& pins, double h,
                          std::uint64_t revision, double iteration_tolerance, bool estimate_error,
                          StepReport& report) {
  State& state = world.state;
  if (estimate_error) {  // the history the step overwrites: v_{n-1} and its step
    older_velocities_ = state.previous_velocities;
    older_step_ = state.has_previous ? state.previous_step : 0.0;
    touched_.swap(touched_before_);
    touched_.assign(static_cast<std::size_t>(state.positions.cols()), 0);
  }
  collide(world, pins, h, revision, iteration_tolerance, report);
  if (estimate_error) {
    std::vector<char> skip = touched_;
    for (std::size_t i = 0; i < touched_before_.size() && i < skip.size(); ++i) {
      skip[i] |= touched_before_[i];
    }
    if (localErrors(world.model, pins, state, older_velocities_, older_step_,
                    world.settings.integrator, skip, step_errors_, estimated_)) {
      frame_error_.add(step_errors_, estimated_);
    }
  }
}

void SubstepPipeline::collide(const SubstepWorld& world, const PinSet& pins, double h,
                              std::uint64_t revision, double iteration_tolerance,
                              StepReport& report) {
  State& state = world.state;
  Colliders& colliders = world.colliders;
  const Model& model = world.model;
  if (!colliders.empty()) {  // an overlap the step starts with is not a motion of the step
    const bool history =
        state.has_previous && state.previous_positions.cols() == state.positions.cols();
    depenetrateStart(colliders, world.movable, state.positions,
                     history ? &state.previous_positions : nullptr);
  }
  const bool loads = !pins.empty();
  // Nothing to collide with: no contacts and no start state to keep.
  const bool collide = !colliders.empty() || world.self_contact != nullptr;
  SolverInput input{model, pins, h, revision, collide ? &contacts_ : nullptr};
  input.iteration_tolerance = iteration_tolerance;
  input.deadline = world.deadline;
  input.min_iterations_at_deadline = world.min_iterations_at_deadline;
  if (loads) reactions_.begin(input, state, world.settings.integrator);
  if (!collide) {
    solve(world, input, report);
    if (loads) reactions_.finish(model, pins, state.positions, world.pin_loads);
    return;
  }
  const Points start = state.positions, start_velocities = state.velocities;
  colliders.advance(h, model.gravity, velocityDecay(model, h));
  // The integrator's own velocity change per metre of correction (from the state before it).
  const double implicit_h =
      StepRecurrence::of(state, h, world.settings.integrator, model.damping).implicit_h;
  CollisionStep collision{h,     model.mass,        world.movable,
                          start, &start_velocities, model.gravity, implicit_h};
  const int threads = resolveThreads(world.settings.threads);
  contacts_.setThreads(threads);
  if (world.self_contact != nullptr) world.self_contact->setThreads(threads);
  contacts_.beginStep(collision, colliders);
  const SolveResult solved = solve(world, input, report);
  // The loads of the solve itself, before the collision response moves soft-pinned particles.
  if (loads) reactions_.finish(model, pins, state.positions, world.pin_loads);
  const Points solved_positions = touched_.empty() ? Points() : state.positions;
  // Only a solver that solved the contacts this step has fresh ball positions to hand over.
  if (state.has_previous) collision.history_velocities = &state.previous_velocities;
  if (solved.used_contacts) {
    if (!touched_.empty()) contacts_.markTouched(touched_);
    contacts_.finish(colliders);
    contacts_.completeFriction(state.positions, state.velocities, collision.history_velocities,
                               iteration_tolerance > 0.0);
    report.contacts += contacts_.activeCount();
  }
  const auto t_self = std::chrono::steady_clock::now();
  // The bound before the colliders: a collider's own correction is never shortened.
  if (world.self_contact != nullptr) {
    report.self_contacts +=
        world.self_contact->limitDisplacement(collision, state.positions, state.velocities);
  }
  auto self_time = std::chrono::steady_clock::now() - t_self;
  report.contacts += resolveCollisions(collision, colliders, state.positions, state.velocities,
                                       solved.used_contacts);
  report.contacts += resolveSphereImpacts(colliders, 2.0 * model.gravity.norm() * h);
  if (world.self_contact != nullptr) {
    const auto t_resolve = std::chrono::steady_clock::now();
    report.self_contacts += world.self_contact->resolve(collision, colliders.ground(),
                                                        state.positions, state.velocities);
    self_time += std::chrono::steady_clock::now() - t_resolve;
    report.self_contact_time += std::chrono::duration<double>(self_time).count();
  }
  // The pairs the proximity stage held go into the next step's solve (mode triangles).
  TriangleSelfContact* triangles =
      world.self_contact != nullptr ? world.self_contact->triangles() : nullptr;
  if (triangles != nullptr) {
    contacts_.swapSelfPairs(triangles->solvePairs());
  } else {
    contacts_.clearSelfPairs();
  }
  report.self_contact_time += contacts_.takeSelfPairSeconds();
  if (!touched_.empty()) {  // moved after the solve: a collider or the cloth itself corrected it
    for (Eigen::Index i = 0; i < state.positions.cols(); ++i) {
      if (state.positions.col(i) != solved_positions.col(i)) touched_[i] = 1;
    }
  }
}

SolveResult SubstepPipeline::solve(const SubstepWorld& world, const SolverInput& input,
                                   StepReport& report) {
  const auto t_solve = std::chrono::steady_clock::now();
  const SolveResult solved = world.solver.step(input, world.settings, world.state);
  report.solve_time +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t_solve).count();
  ++report.substeps;
  report.iterations = solved.iterations;
  report.total_iterations += solved.iterations;
  report.iteration_error = std::max(report.iteration_error, solved.iteration_error);
  // Each earlier substep's iteration error moves the cloth once more in this one (StepReport::
  // carried_iteration_error): the sum over substeps of the errors so far.
  iteration_errors_ += solved.iteration_error;
  report.carried_iteration_error += iteration_errors_;
  report.convergence = solved.convergence;
  report.converged = solved.converged;
  if (solved.midpoint_fallback) ++report.midpoint_fallbacks;
  if (solved.cut) ++report.cut_substeps;
  return solved;
}

}  // namespace cloth_sim
