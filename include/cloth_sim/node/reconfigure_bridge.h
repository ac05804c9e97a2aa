/// @file reconfigure_bridge.h
/// dynamic_reconfigure's ClothSimConfig <-> the simulation and the node's own tunables: what a
/// request changes, what it refuses and why, and the config that reflects what is in use. Pure:
/// no ROS handle, no master (the node's onReconfigure only logs what apply() reports).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <cloth_sim/ClothSimConfig.h>

#include "cloth_sim/core/simulation/frame_budget.h"
#include "cloth_sim/core/simulation/simulation.h"
#include "cloth_sim/node/marker_builder.h"

namespace cloth_sim::node {

/// What applying one field of a request did.
struct FieldOutcome {
  std::string field;  ///< the reconfigure name, e.g. "structural_stiffness"
  bool applied = false;
  std::string why;  ///< when refused: the message of the core (or of the rule) that refused it
};

/// The frame budget for @p budget_ms (ms, > 0 on; 0 off: std::nullopt), picking each frame's
/// substeps within settings::kSubsteps' range. Throws std::invalid_argument, naming the value
/// @p what, when @p budget_ms is outside settings::kFrameBudget's range or longer than the
/// frame @p frame_s (s, the scene's time_step): a frame given more than its period runs slower
/// than real time.
std::optional<FrameBudget> frameBudgetFor(double budget_ms, double frame_s,
                                          const std::string& what = "budget_ms");

/// Maps ClothSimConfig onto a Simulation, the node's frame budget and the cloth's colour mode,
/// which it changes in place (all three must outlive it).
///
/// A request changes each field that differs from current(), one at a time in the cfg's order:
/// the stiffness of each spring family (Simulation::setFamilyStiffness), damping, solver,
/// color_mode, iterations and substeps (Simulation::setSolverSettings), budget_ms (within the
/// frame; off restores the configured substeps) and
/// self_collision (Simulation::setSelfContact, keeping the thickness and friction). A field the
/// core refuses (a negative stiffness, a family the object lacks, an unknown solver, 0
/// iterations, ...) is left as it was and put back in the request, which the server then
/// reports to every client; the others still apply.
class ReconfigureBridge {
 public:
  /// Changes @p sim, the node's frame budget @p budget (std::nullopt = off) and the cloth's
  /// @p color_mode; each must outlive the bridge.
  ReconfigureBridge(Simulation& sim, std::optional<FrameBudget>& budget, ColorMode& color_mode);

  /// The config in use: the simulation's stiffnesses, damping, solver, iterations, substeps and
  /// self-collision, the frame budget (ms, 0 = off) and the colour mode.
  ClothSimConfig current() const;

  /// Applies @p config's changed fields as above; a refused field gets its current value back.
  /// Returns one outcome per changed field, in the order applied.
  std::vector<FieldOutcome> apply(ClothSimConfig& config);

  /// The substeps the user set (the scene's, ~substeps or the last reconfigured value; 0 =
  /// chosen by the error estimate), which a frame budget may change frame by frame.
  int configuredSubsteps() const { return configured_substeps_; }

 private:
  /// budget_ms turned off: the configured substeps come back (or, with automatic substeps, the
  /// error controller's own cap), not the budget's last choice.
  void restoreConfiguredSubsteps();

  Simulation& sim_;
  std::optional<FrameBudget>& budget_;
  ColorMode& color_mode_;
  int configured_substeps_;
};

}  // namespace cloth_sim::node
