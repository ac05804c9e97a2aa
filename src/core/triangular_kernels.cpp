#include "cloth_sim/core/triangular_kernels.h"

// The vector type below never crosses this file's interface (only pointers do), so the ABI note
// GCC gives for 32-byte vectors in a build without AVX does not apply.
#pragma GCC diagnostic ignored "-Wpsabi"

namespace cloth_sim {
namespace {

// One node (x, y, z, pad) as a GCC/Clang vector: 2 SSE2 operations in the portable build, one
// AVX2 operation in the x86-64-v3 clone picked at load time (CLOTH_SIM_CLONES below).
typedef double Node __attribute__((vector_size(32), aligned(8)));

inline Node load(const double* p) { return *reinterpret_cast<const Node*>(p); }
inline void store(double* p, Node v) { *reinterpret_cast<Node*>(p) = v; }

/// acc -= sum_k value[k] x[index[k]] over [begin, end), four accumulators.
inline Node gatherDot(const int* index, const double* value, int begin, int end, const double* x,
                      Node acc) {
  Node a1 = {0, 0, 0, 0}, a2 = a1, a3 = a1;
  int k = begin;
  for (; k + 3 < end; k += 4) {
    acc -= value[k] * load(x + kNodeStride * index[k]);
    a1 -= value[k + 1] * load(x + kNodeStride * index[k + 1]);
    a2 -= value[k + 2] * load(x + kNodeStride * index[k + 2]);
    a3 -= value[k + 3] * load(x + kNodeStride * index[k + 3]);
  }
  for (; k < end; ++k) acc -= value[k] * load(x + kNodeStride * index[k]);
  return (acc + a1) + (a2 + a3);
}

}  // namespace

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define CLOTH_SIM_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define CLOTH_SIM_CLONES
#endif

CLOTH_SIM_CLONES void forwardSolve3(const LowerFactor& f, double* x) {
  const int* start = f.row_start.data();
  const int* index = f.row_col.data();
  const double* value = f.row_value.data();
  const double* inv = f.inv_diagonal.data();
  for (int i = 0; i < f.size; ++i) {
    const Node acc = gatherDot(index, value, start[i], start[i + 1], x, load(x + kNodeStride * i));
    store(x + kNodeStride * i, acc * inv[i]);
  }
}

CLOTH_SIM_CLONES void backwardSolve3(const LowerFactor& f, double* x) {
  const int* start = f.col_start.data();
  const int* index = f.col_row.data();
  const double* value = f.col_value.data();
  const double* inv = f.inv_diagonal.data();
  for (int j = f.size - 1; j >= 0; --j) {
    const Node acc = gatherDot(index, value, start[j], start[j + 1], x, load(x + kNodeStride * j));
    store(x + kNodeStride * j, acc * inv[j]);
  }
}

}  // namespace cloth_sim
