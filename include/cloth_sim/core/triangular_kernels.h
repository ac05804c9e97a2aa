/// @file triangular_kernels.h
/// Hand-written triangular solves for the global step of local/global (Liu et al. 2013, sec. 4):
/// one scalar factor L, three right-hand sides (x, y, z) solved in the same pass.
#pragma once

#include "cloth_sim/core/cholmod_factor.h"

namespace cloth_sim {

/// Doubles per node in the padded node layout of the kernels: x, y, z and a pad slot kept at 0,
/// so one node is one 32-byte vector (AVX2) and its three coordinates share every load of L.
constexpr int kNodeStride = 4;

/// Forward substitution L Z = B over the rows of L (CSR), in place on @p x (n x kNodeStride,
/// node k of the factor's order at x[4k]). Each row is a gather dot product with four
/// independent accumulators, so it runs at load throughput rather than FMA latency.
void forwardSolve3(const LowerFactor& factor, double* x);

/// Backward substitution L^T X = Z over the columns of L (CSC), in place; same layout.
void backwardSolve3(const LowerFactor& factor, double* x);

/// Solves L L^T X = B in place for the three columns together: forward then backward. Reads
/// the factor twice (once per direction) where a column-at-a-time library solve reads it six
/// times. Result matches a library solve to round-off (a test checks 1e-12).
inline void solveFused3(const LowerFactor& factor, double* x) {
  forwardSolve3(factor, x);
  backwardSolve3(factor, x);
}

}  // namespace cloth_sim
