/// @file local_step.h
/// Stateless kernels of the local step of local/global (Liu et al. 2013, sec. 4.2) over
/// structure-of-arrays springs and the padded node layout of supernodal_solves.h.
#pragma once

#include <vector>

#include "cloth_sim/core/linalg/node_buffer.h"
#include "cloth_sim/core/linalg/supernodal_solves.h"
#include "cloth_sim/core/linalg/types.h"

namespace cloth_sim {

/// The springs of the local step, in a solver's node order (free nodes first, in the factor's
/// order, then hard-pinned ones), sorted by their first node for locality.
struct SpringTable {
  std::vector<int> a, b;           ///< end nodes; a spring with two pinned ends is not listed
  std::vector<double> weight;      ///< h^2 k r, kg m: the J d coefficient of eq. 12
  std::vector<double> half_k;      ///< k / 2, N/m
  std::vector<double> rest;        ///< r, m
  std::size_t size() const { return a.size(); }
  void add(int i, int j, double w, double k, double r);
  /// Sorts the springs by (min node, max node) so the local step walks memory forwards.
  void sortByNode();
};

/// Local step fused with the J d product (Liu et al. 2013, eqs. 10 and 12): for every spring,
/// d_s = r_s u with u = (x_a - x_b)/|x_a - x_b| (+x for a collapsed spring), and
/// rhs_a += h^2 k_s d_s, rhs_b -= h^2 k_s d_s. Returns the spring energy
/// sum_s 1/2 k_s (|x_a - x_b| - r_s)^2 (J) at @p x, which the objective g needs and which
/// costs nothing extra here. @p rhs must have a row for every node a spring refers to.
double localStep3(const SpringTable& springs, const double* x, double* rhs);

/// sum_s 1/2 k_s (|x_a - x_b| - r_s)^2 (J): the energy localStep3 returns, without the rhs.
double springEnergy3(const SpringTable& springs, const double* x);

/// sum_i m_i (1/2 |x_i - y_i|^2 - h^2 g . x_i) over @p count nodes (kg m^2): the inertia and
/// gravity part of the implicit Euler objective g (implicit_euler_problem.h).
double inertiaAndGravity(const double* x, const double* y, const double* mass, int count,
                         const Vec3& gravity, double h2);

}  // namespace cloth_sim
