/// @file pin_reactions.h
/// The force the cloth exerts on each pin over one implicit step, read from the solve
/// (docs/method.md, "Pin forces").
#pragma once

#include <vector>

#include "cloth_sim/core/linalg/types.h"
#include "cloth_sim/core/model/model.h"
#include "cloth_sim/core/model/pins.h"
#include "cloth_sim/core/solvers/solver.h"

namespace cloth_sim {

/// Pin loads of one implicit step: call begin() with the state the step starts from, let the
/// solver step, then finish() with the end positions.
///
/// A hard pin holds its particle i on the target with a force F_i that makes the implicit step's
/// stationarity condition hold for i too (ImplicitStepProblem: m_i (x_i - y_i) / h_i^2 =
/// f_i(x) + F_i). The cloth exerts the opposite on the pin:
///
///   load_i = -F_i = f_i(x) - m_i (x_i - y_i) / h_i^2   (N),
///
/// f_i the spring forces on i plus its weight m_i g, y_i the free inertial prediction of i (the
/// one ImplicitStepProblem::build gives an unpinned particle, damping included), h_i the step of
/// the h_i^2 E term (h, or 2h/3 for BDF2). A soft pin of stiffness k is pulled by its spring:
/// load = k (x_i - target). Summed over the pins of a cloth at rest, the loads are its weight;
/// for a cloth whose pins accelerate at a, they are m (g - a) (so m (g + a) downwards when lifted
/// upwards at a). The explicit solvers get the same formula (an estimate: their step is not this
/// minimisation). Contact forces on a hard-pinned particle are not included: collisions skip it.
class PinReactions {
 public:
  /// Keeps y_i and h_i of every hard-pinned particle of input.pins for the step of input.h
  /// from @p state (x_n, v_n and, for BDF2, its history) with @p integrator.
  void begin(const SolverInput& input, const State& state, Integrator integrator);
  /// The load (N) on each pin of @p pins (the same set as begin's), in pins.pins() order, for
  /// the step that ended at positions @p x.
  void finish(const Model& model, const PinSet& pins, const Points& x,
              std::vector<Vec3>& loads) const;

 private:
  std::vector<Vec3> inertial_;  ///< y_i per pin (hard pins only; soft ones unused), m
  double implicit_h_ = 0.0;     ///< h_i, s
  std::vector<int> pin_of_;     ///< particle -> index in pins.pins(), -1 if unpinned
};

}  // namespace cloth_sim
