#include "cloth_sim/core/solvers/pin_reactions.h"

#include "cloth_sim/core/solvers/implicit_euler_problem.h"

namespace cloth_sim {

void PinReactions::begin(const SolverInput& input, const State& state, Integrator integrator) {
  // The same prediction as ImplicitStepProblem::build, for the pinned particles only (build
  // overwrites theirs with the target).
  const Model& model = input.model;
  const PinSet& pins = input.pins;
  const StepRecurrence r = StepRecurrence::of(state, input.h, integrator, model.damping);
  implicit_h_ = r.implicit_h;
  inertial_.resize(pins.size());
  pin_of_.assign(model.particleCount(), -1);
  for (std::size_t p = 0; p < pins.size(); ++p) {
    const int i = pins.pins()[p].vertex;
    pin_of_[i] = static_cast<int>(p);
    inertial_[p] = r.inertial(state, i);
  }
}

void PinReactions::finish(const Model& model, const PinSet& pins, const Points& x,
                          std::vector<Vec3>& loads) const {
  loads.assign(pins.size(), Vec3::Zero());
  // Spring forces on the pinned particles only: one pass over the springs, most skipped.
  const Springs& s = model.springs;
  for (std::size_t k = 0; k < s.size(); ++k) {
    const int a = s.first[k], b = s.second[k];
    const int pa = pin_of_[a], pb = pin_of_[b];
    if (pa < 0 && pb < 0) continue;
    const Vec3 d = x.col(a) - x.col(b);
    const double length = d.norm();
    if (length == 0.0) continue;  // no direction: the spring pulls nowhere
    const Vec3 f = -s.stiffness[k] * (length - s.rest_length[k]) / length * d;  // on a
    if (pa >= 0) loads[pa] += f;
    if (pb >= 0) loads[pb] -= f;
  }
  const double inv_h2 = 1.0 / (implicit_h_ * implicit_h_);
  for (std::size_t p = 0; p < pins.size(); ++p) {
    const Pin& pin = pins.pins()[p];
    const int i = pin.vertex;
    if (pin.isHard()) {
      loads[p] += model.mass[i] * model.gravity - model.mass[i] * inv_h2 * (x.col(i) - inertial_[p]);
    } else {
      loads[p] = pin.stiffness * (x.col(i) - pin.target);
    }
  }
}

}  // namespace cloth_sim
