/// @file model.h
/// The immutable parameters of a mass-spring object (MuJoCo's "model", apart from the state).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "cloth_sim/core/linalg/types.h"
#include "cloth_sim/core/settings/settings_table.h"

namespace cloth_sim {

/// Spring families of a cloth grid (docs/method.md, "The model"); each has its own stiffness.
enum class SpringFamily : std::uint8_t {
  kStructural = 0,  ///< row/column neighbours (or mesh edges)
  kShear = 1,       ///< quad diagonals
  kBending = 2,     ///< distance-2 neighbours along rows and columns (or across mesh edges)
};
constexpr int kSpringFamilyCount = 3;

/// Lower-case name used in scene files and messages: "structural", "shear", "bending".
const char* springFamilyName(SpringFamily family);
/// The rule of @p family's stiffness: settings::kStructuralStiffness, kShearStiffness or
/// kBendingStiffness.
const Setting& stiffnessSetting(SpringFamily family);

/// Springs in structure-of-arrays layout. Spring s joins particles first[s] and second[s] with
/// Hooke energy 1/2 stiffness[s] (|x_i - x_j| - rest_length[s])^2.
struct Springs {
  std::vector<int> first;            ///< index of one end
  std::vector<int> second;           ///< index of the other end
  std::vector<double> rest_length;   ///< m, > 0
  std::vector<double> stiffness;     ///< N/m, >= 0
  std::vector<SpringFamily> family;  ///< family the spring belongs to

  std::size_t size() const { return first.size(); }
  void add(int i, int j, double rest, double k, SpringFamily f);
};

/// Everything about a mass-spring object that does not change while it moves: its physical
/// parameters (particles, springs, damping, gravity). The time step is not one of them: it is
/// an input of each solve (SolverInput::h). Edited only between steps (through Simulation),
/// which then refactors what depends on it.
struct Model {
  Eigen::VectorXd mass;            ///< kg, lumped mass of each particle, > 0
  Springs springs;                 ///< all springs of all families
  Eigen::Matrix3Xi triangles;      ///< surface triangles (vertex indices), for display/collision
  Vec3 gravity = standardGravity();///< m/s^2
  /// Linear drag rate gamma (1/s): a free particle's velocity decays as exp(-gamma t)
  /// (mass-proportional damping, force -gamma m v, like still air). 0 = undamped.
  double damping = 0.0;

  int particleCount() const { return static_cast<int>(mass.size()); }
  /// Sets the stiffness (N/m) of every spring of @p family.
  void setFamilyStiffness(SpringFamily family, double stiffness);
  /// Stiffness (N/m) of the first spring of @p family; 0 if the family has no spring.
  double familyStiffness(SpringFamily family) const;
  /// Number of springs in @p family.
  int familySize(SpringFamily family) const;
  /// Throws std::invalid_argument naming the first inconsistent field: a spring index out of
  /// range, a non-finite gravity, or a number its entry of settings_table.h refuses (mass, rest
  /// length, stiffness by family, damping: Setting::require).
  void validate() const;
};

/// Kinematic state of the particles: what changes every step.
struct State {
  Points positions;   ///< m
  Points velocities;  ///< m/s
  double time = 0.0;  ///< s of simulated time
  /// The state one step before (x_{n-1}, v_{n-1}) and that step's size, written by every
  /// implicit step for Integrator::kBdf2 (and the error estimate). Valid only when has_previous:
  /// false at the start, and cleared by Simulation on reset, rollback or a pin-set change (then
  /// the next step is an implicit Euler step); a new step size keeps it (variable-step BDF2).
  /// The explicit solvers clear it too.
  Points previous_positions;   ///< m
  Points previous_velocities;  ///< m/s
  double previous_step = 0.0;  ///< s, h_{n-1}: from previous_positions to positions
  bool has_previous = false;

  /// A state at rest at @p rest_positions.
  static State atRest(const Points& rest_positions);
  /// True when every position and velocity is finite.
  bool allFinite() const;
};

}  // namespace cloth_sim
