/// @file types.h
/// Basic aliases shared by the whole core. SI units everywhere (m, kg, s, N); z is up (REP-103).
#pragma once

#include <Eigen/Core>

namespace cloth_sim {

/// A point or vector in world coordinates (m, m/s or N depending on use).
using Vec3 = Eigen::Vector3d;

/// Per-particle 3D quantities of N particles: column i is particle i (x, y, z).
/// Column-major 3 x N, so one particle's coordinates are contiguous.
using Points = Eigen::Matrix3Xd;

/// Standard gravity (m/s^2) pointing down -z, the default of every scene.
inline Vec3 standardGravity() { return Vec3(0.0, 0.0, -9.81); }

}  // namespace cloth_sim
