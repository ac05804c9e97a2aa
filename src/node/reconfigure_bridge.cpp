#include "cloth_sim/node/reconfigure_bridge.h"

#include <cstdio>
#include <exception>
#include <stdexcept>

#include "cloth_sim/core/settings/settings_table.h"

namespace cloth_sim::node {
namespace {

/// The family a reconfigure field sets.
struct FamilyField {
  SpringFamily family;
  double ClothSimConfig::*value;
};
constexpr FamilyField kFamilyFields[] = {
    {SpringFamily::kStructural, &ClothSimConfig::structural_stiffness},
    {SpringFamily::kShear, &ClothSimConfig::shear_stiffness},
    {SpringFamily::kBending, &ClothSimConfig::bending_stiffness},
};

/// Applies one field of a request: nothing when it equals @p was's, else @p set with the new
/// value; a refusal puts @p was's value back into @p config. Appends the outcome to @p out.
template <class T, class Set>
void applyField(const std::string& name, T ClothSimConfig::*field, ClothSimConfig& config,
                const ClothSimConfig& was, Set&& set, std::vector<FieldOutcome>& out) {
  if (config.*field == was.*field) return;
  try {
    set(config.*field);
    out.push_back({name, true, ""});
  } catch (const std::exception& e) {
    out.push_back({name, false, e.what()});
    config.*field = was.*field;
  }
}

}  // namespace

std::optional<FrameBudget> frameBudgetFor(double budget_ms, double frame_s,
                                          const std::string& what) {
  settings::kFrameBudget.require(budget_ms, what);
  if (!(budget_ms > 0.0)) return std::nullopt;
  if (budget_ms > 1e3 * frame_s) {
    // A budget beyond the frame lets the substeps grow until the simulation runs slower than
    // real time (100 ms on a 16.7 ms frame: 259 substeps, 0.26x real time).
    char buf[256];
    std::snprintf(buf, sizeof buf,
                  "%s %g must be at most the frame, %.3f ms (the scene's time_step: a frame "
                  "that takes longer than its period runs slower than real time)",
                  what.c_str(), budget_ms, 1e3 * frame_s);
    throw std::invalid_argument(buf);
  }
  return FrameBudget(1e-3 * budget_ms, 1, settings::kSubsteps.range.max);
}

ReconfigureBridge::ReconfigureBridge(Simulation& sim, std::optional<FrameBudget>& budget,
                                     ColorMode& color_mode)
    : sim_(sim),
      budget_(budget),
      color_mode_(color_mode),
      configured_substeps_(sim.solverSettings().substeps) {}

ClothSimConfig ReconfigureBridge::current() const {
  ClothSimConfig c;
  for (const FamilyField& f : kFamilyFields) c.*f.value = sim_.model().familyStiffness(f.family);
  c.damping = sim_.model().damping;
  c.solver = sim_.solver().name();
  c.iterations = sim_.solverSettings().max_iterations;
  c.substeps = sim_.solverSettings().substeps;
  c.error_tolerance = sim_.solverSettings().error_tolerance;
  c.budget_ms = budget_ ? 1e3 * budget_->budget() : 0.0;
  c.self_collision = sim_.selfContact() != nullptr;
  c.color_mode = colorModeName(color_mode_);
  return c;
}

std::vector<FieldOutcome> ReconfigureBridge::apply(ClothSimConfig& config) {
  const ClothSimConfig was = current();
  std::vector<FieldOutcome> out;
  for (const FamilyField& f : kFamilyFields) {
    applyField(
        std::string(springFamilyName(f.family)) + "_stiffness", f.value, config, was,
        [&](double k) { sim_.setFamilyStiffness(f.family, k); }, out);
  }
  applyField(
      "damping", &ClothSimConfig::damping, config, was, [&](double d) { sim_.setDamping(d); }, out);
  applyField(
      "solver", &ClothSimConfig::solver, config, was,
      [&](const std::string& name) { sim_.setSolver(name); }, out);
  applyField(
      "color_mode", &ClothSimConfig::color_mode, config, was,
      [&](const std::string& name) { color_mode_ = colorModeFromName(name); }, out);
  auto solverSetting = [&](int SolverSettings::*setting) {
    return [this, setting](int value) {
      SolverSettings settings = sim_.solverSettings();
      settings.*setting = value;
      sim_.setSolverSettings(settings);  // validates
    };
  };
  applyField("iterations", &ClothSimConfig::iterations, config, was,
             solverSetting(&SolverSettings::max_iterations), out);
  applyField(
      "substeps", &ClothSimConfig::substeps, config, was,
      [&](int substeps) {
        solverSetting(&SolverSettings::substeps)(substeps);
        configured_substeps_ = substeps;  // what budget_ms 0 comes back to
      },
      out);
  applyField(
      "error_tolerance", &ClothSimConfig::error_tolerance, config, was,
      [&](double tolerance) {
        SolverSettings settings = sim_.solverSettings();
        settings.error_tolerance = tolerance;
        sim_.setSolverSettings(settings);  // validates (substeps 0 needs a tolerance)
      },
      out);
  applyField(
      "budget_ms", &ClothSimConfig::budget_ms, config, was,
      [&](double ms) {
        std::optional<FrameBudget> next = frameBudgetFor(ms, sim_.frameTime());
        const bool turned_off = budget_.has_value() && !next.has_value();
        budget_ = std::move(next);
        if (turned_off) restoreConfiguredSubsteps();
      },
      out);
  applyField(
      "self_collision", &ClothSimConfig::self_collision, config, was,
      [&](bool on) {
        SelfContactSettings self = sim_.options().self_contact;
        self.enabled = on;
        sim_.setSelfContact(self);
      },
      out);
  return out;
}

void ReconfigureBridge::restoreConfiguredSubsteps() {
  SolverSettings settings = sim_.solverSettings();
  if (configured_substeps_ == 0 || settings.automaticSubsteps()) {
    // The error controller chooses again, up to its own cap.
    sim_.setSubstepLimit(Simulation::kMaxAutomaticSubsteps);
    return;
  }
  if (settings.substeps == configured_substeps_) return;
  settings.substeps = configured_substeps_;
  sim_.setSolverSettings(settings);  // a count it accepted before
}

}  // namespace cloth_sim::node
