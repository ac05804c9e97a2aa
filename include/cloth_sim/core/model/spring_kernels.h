/// @file spring_kernels.h
/// Stateless kernels over the structure-of-arrays spring data (PositionBasedDynamics style).
#pragma once

#include <Eigen/Core>

#include "cloth_sim/core/model/model.h"
#include "cloth_sim/core/linalg/types.h"

namespace cloth_sim {

/// Total Hooke energy sum_s 1/2 k_s (|x_i - x_j| - r_s)^2, in J.
double springEnergy(const Springs& springs, const Points& x);

/// Adds the spring forces f = -dE/dx (N) into @p forces (3 x N, not cleared).
void addSpringForces(const Springs& springs, const Points& x, Points& forces);

/// Largest strain |l - r| / r over all springs (dimensionless); 0 with no spring.
double maxStrain(const Springs& springs, const Points& x);

/// Hessian block d^2E/dx_i^2 of one spring's energy 1/2 k (|d| - r)^2 with d = x_i - x_j:
/// k (u u^T + (1 - r/|d|) (I - u u^T)), u = d/|d|. The full spring Hessian is [H -H; -H H].
/// Under compression (|d| < r) the transverse term is negative; with @p clamp_psd it is clamped
/// at 0, which makes the block positive semi-definite (Choi and Ko 2002).
Eigen::Matrix3d springHessianBlock(const Vec3& d, double rest_length, double stiffness,
                                   bool clamp_psd = true);

/// Unit direction of @p d, or +x when |d| is too small to define one (a collapsed spring:
/// its energy 1/2 k r^2 is the same for every direction).
Vec3 safeDirection(const Vec3& d);

}  // namespace cloth_sim
