#include "cloth_sim/core/solvers/solver.h"

#include <algorithm>

#include <cassert>
#include <cstddef>
#include <stdexcept>

#include "cloth_sim/core/solvers/registry.h"

namespace cloth_sim {
namespace {

/// The names of @p all (an enum's values), as @p name gives them.
template <typename Enum, std::size_t N>
std::vector<std::string> namesOf(const Enum (&all)[N], const char* (*name)(Enum)) {
  std::vector<std::string> names;
  for (Enum e : all) names.emplace_back(name(e));
  return names;
}

/// The value of @p all called @p wanted; throws naming @p what and the known names if none.
template <typename Enum, std::size_t N>
Enum fromName(const Enum (&all)[N], const char* (*name)(Enum), const std::string& wanted,
              const char* what) {
  for (Enum e : all) {
    if (wanted == name(e)) return e;
  }
  std::string list;
  for (const auto& n : namesOf(all, name)) list += (list.empty() ? "" : ", ") + n;
  throw std::invalid_argument(std::string("unknown ") + what + " '" + wanted + "' (known: " + list +
                              ")");
}

}  // namespace

const char* linearSolverName(LinearSolver solver) {
  switch (solver) {
    case LinearSolver::kFused: return "fused";
    case LinearSolver::kCholmod: return "cholmod";
    case LinearSolver::kEigen: return "eigen";
    case LinearSolver::kFusedFloat: return "fused_float";
  }
  return "unknown";
}

std::vector<std::string> linearSolverNames() {
  return namesOf(kLinearSolvers, &linearSolverName);
}

LinearSolver linearSolverFromName(const std::string& name) {
  return fromName(kLinearSolvers, &linearSolverName, name, "linear solver");
}

const char* integratorName(Integrator integrator) {
  switch (integrator) {
    case Integrator::kImplicitEuler: return "implicit_euler";
    case Integrator::kBdf2: return "bdf2";
    case Integrator::kImplicitMidpoint: return "implicit_midpoint";
  }
  return "unknown";
}

std::vector<std::string> integratorNames() { return namesOf(kIntegrators, &integratorName); }

Integrator integratorFromName(const std::string& name) {
  return fromName(kIntegrators, &integratorName, name, "integrator");
}

std::string SolverParam::field() const {
  // "solver.<solver>.<field>": after the second dot.
  const std::string full = name;
  const auto first = full.find('.');
  const auto second = first == std::string::npos ? first : full.find('.', first + 1);
  return second == std::string::npos ? full : full.substr(second + 1);
}

double SolverParams::number(const SolverParam& param) const {
  for (const auto& [p, value] : values_) {
    if (p == &param) return value;
  }
  return param.default_value;
}

int SolverParams::integer(const SolverParam& param) const {
  assert(param.integer);
  return static_cast<int>(number(param));
}

void SolverParams::set(const SolverParam& param, double value) {
  for (auto& [p, v] : values_) {
    if (p == &param) {
      v = value;
      return;
    }
  }
  values_.emplace_back(&param, value);
}

void SolverParams::validate() const {
  for (const auto& [p, value] : values_) p->require(value);
}

bool Solver::supports(Integrator integrator) const {
  return solverEntry(name()).capabilities.supports(integrator);
}

void requireIntegrator(const Solver& solver, Integrator integrator) {
  if (solver.supports(integrator)) return;
  std::string implicit;
  for (const SolverEntry& entry : solverRegistry()) {
    if (!entry.capabilities.supports(integrator)) continue;
    implicit += (implicit.empty() ? "" : ", ") + std::string(entry.name);
  }
  throw std::invalid_argument(std::string("solver.integrator = ") + integratorName(integrator) +
                              " is not supported by " + solver.name() +
                              " (an explicit scheme of its own; solvers that support it: " +
                              implicit + ")");
}

void requireErrorControl(const Solver& solver, const SolverSettings& settings) {
  if (settings.error_tolerance <= 0.0 || solverEntry(solver.name()).capabilities.tolerance) return;
  std::string able;
  for (const SolverEntry& entry : solverRegistry()) {
    if (entry.capabilities.tolerance) able += (able.empty() ? "" : ", ") + std::string(entry.name);
  }
  throw std::invalid_argument(
      std::string("solver.error_tolerance > 0 (error control) is not supported by ") +
      solver.name() + ", which does not iterate to a tolerance (solvers that do: " + able +
      "); set solver.error_tolerance: 0 and a number of solver.substeps");
}

void Solver::requireSettings(const SolverSettings& settings) const {
  requireIntegrator(*this, settings.integrator);
  requireErrorControl(*this, settings);
}

double IterationError::add(double change) {
  ++changes_;
  const double previous = last_change_;
  last_change_ = change;
  if (change == 0.0) {  // at the fixed point
    estimate_ = 0.0;
  } else if (changes_ < kFirstTrusted || !(previous > 0.0)) {
    estimate_ = std::numeric_limits<double>::infinity();
  } else {
    const double rate = std::min(kMaxRate, change / previous);
    estimate_ = change * rate / (1.0 - rate);
  }
  return estimate_;
}

void SolverSettings::validate() const {
  settings::kIterations.require(max_iterations);
  settings::kSubsteps.require(substeps);
  settings::kThreads.require(threads);
  settings::kTolerance.require(tolerance);
  settings::kErrorTolerance.require(error_tolerance);
  if (substeps == 0 && error_tolerance <= 0.0) {
    throw std::invalid_argument(
        "solver.substeps 0 (chosen by the error estimate) needs solver.error_tolerance > 0");
  }
  params.validate();
}

}  // namespace cloth_sim
