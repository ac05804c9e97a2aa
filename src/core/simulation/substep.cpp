#include "cloth_sim/core/simulation/substep.h"

#include <chrono>

#include "cloth_sim/core/collision/sphere_impacts.h"
#include "cloth_sim/core/solvers/implicit_euler_problem.h"

namespace cloth_sim {

void SubstepPipeline::run(const SubstepWorld& world, const PinSet& pins, double h,
                          std::uint64_t revision, StepReport& report) {
  State& state = world.state;
  Colliders& colliders = world.colliders;
  const Model& model = world.model;
  const bool loads = !pins.empty();
  // Nothing to collide with: no contacts and no start state to keep.
  const bool collide = !colliders.empty() || world.self_contact != nullptr;
  const SolverInput input{model, pins, h, revision, collide ? &contacts_ : nullptr};
  if (loads) reactions_.begin(input, state, world.settings.integrator);
  if (!collide) {
    solve(world, input, report);
    if (loads) reactions_.finish(model, pins, state.positions, world.pin_loads);
    return;
  }
  const Points start = state.positions, start_velocities = state.velocities;
  colliders.advance(h, model.gravity, velocityDecay(model, h));
  const CollisionStep collision{h,     model.mass,        world.movable,
                                start, &start_velocities, model.gravity};
  contacts_.setThreads(resolveThreads(world.settings.threads));
  if (world.self_contact != nullptr) world.self_contact->setThreads(resolveThreads(world.settings.threads));
  contacts_.beginStep(collision, colliders);
  const SolveResult solved = solve(world, input, report);
  // The loads of the solve itself, before the collision response moves soft-pinned particles.
  if (loads) reactions_.finish(model, pins, state.positions, world.pin_loads);
  // Only a solver that solved the contacts this step has fresh ball positions to hand over.
  if (solved.used_contacts) {
    contacts_.finish(colliders);
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
}

SolveResult SubstepPipeline::solve(const SubstepWorld& world, const SolverInput& input,
                                   StepReport& report) {
  const auto t_solve = std::chrono::steady_clock::now();
  const SolveResult solved = world.solver.step(input, world.settings, world.state);
  report.solve_time +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t_solve).count();
  ++report.substeps;
  report.iterations = solved.iterations;
  report.convergence = solved.convergence;
  report.converged = solved.converged;
  if (solved.midpoint_fallback) ++report.midpoint_fallbacks;
  return solved;
}

}  // namespace cloth_sim
