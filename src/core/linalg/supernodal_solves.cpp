#include "cloth_sim/core/linalg/supernodal_solves.h"

#include <algorithm>
#include <stdexcept>

// The vector type below never crosses this file's interface (only pointers do), so the ABI note
// GCC gives for 32-byte vectors in a build without AVX does not apply.
#pragma GCC diagnostic ignored "-Wpsabi"

namespace cloth_sim {
namespace {

// One node (x, y, z, pad) as a GCC/Clang vector: 2 SSE2 operations in the portable build, one
// AVX2 operation in the x86-64-v3 clone picked at load time (CLOTH_SIM_CLONES below).
typedef double Node __attribute__((vector_size(32), aligned(8)));

// Everything below is forced inline into the two clones of forwardSolve3 / backwardSolve3, so
// it is compiled once per target (a plain call would run the portable code in both).
#define CLOTH_SIM_INLINE inline __attribute__((always_inline))

CLOTH_SIM_INLINE Node load(const double* p) { return *reinterpret_cast<const Node*>(p); }
CLOTH_SIM_INLINE void store(double* p, Node v) { *reinterpret_cast<Node*>(p) = v; }
CLOTH_SIM_INLINE double* node(double* x, int k) { return x + kNodeStride * k; }

/// Forward step of one supernode of width W starting at column c0.
template <int W>
CLOTH_SIM_INLINE void forwardSupernode(int c0, const int* rows, int count, const double* block,
                             const double* inv, double* x) {
  Node xc[W];
  for (int c = 0; c < W; ++c) {  // the dense diagonal block, column by column
    Node acc = load(node(x, c0 + c));
    for (int p = 0; p < c; ++p) acc -= block[c * W + p] * xc[p];
    xc[c] = acc * inv[c0 + c];
    store(node(x, c0 + c), xc[c]);
  }
  const double* v = block + W * W;
  for (int i = 0; i < count; ++i, v += W) {  // each row below: x_r -= sum_c L_rc x_c
    double* xr = node(x, rows[i]);
    Node acc = load(xr);
    for (int c = 0; c < W; ++c) acc -= v[c] * xc[c];
    store(xr, acc);
  }
}

/// Backward step of one supernode of width W starting at column c0.
template <int W>
CLOTH_SIM_INLINE void backwardSupernode(int c0, const int* rows, int count, const double* block,
                              const double* inv, double* x) {
  // U rows per round so that U * W >= 8 chains of multiply-adds are in flight.
  constexpr int U = W >= 8 ? 1 : (W >= 4 ? 2 : (W >= 2 ? 4 : 8));
  Node acc[U][W] = {};
  const double* v = block + W * W;
  int i = 0;
  for (; i + U <= count; i += U) {
    for (int u = 0; u < U; ++u) {
      const Node xr = load(node(x, rows[i + u]));
      for (int c = 0; c < W; ++c) acc[u][c] += v[(i + u) * W + c] * xr;
    }
  }
  for (; i < count; ++i) {
    const Node xr = load(node(x, rows[i]));
    for (int c = 0; c < W; ++c) acc[0][c] += v[i * W + c] * xr;
  }
  for (int c = W - 1; c >= 0; --c) {  // the diagonal block, transposed, last column first
    Node sum = acc[0][c];
    for (int u = 1; u < U; ++u) sum += acc[u][c];
    Node value = load(node(x, c0 + c)) - sum;
    for (int p = c + 1; p < W; ++p) value -= block[p * W + c] * load(node(x, c0 + p));
    store(node(x, c0 + c), value * inv[c0 + c]);
  }
}

template <bool kForward>
CLOTH_SIM_INLINE void solveSupernode(const SupernodalFactor& f, int s, double* x) {
  const int c0 = f.first_column[s], w = f.first_column[s + 1] - c0;
  const int* rows = f.rows.data() + f.row_start[s];
  const int count = f.row_start[s + 1] - f.row_start[s];
  const double* block = f.values.data() + f.value_start[s];
  const double* inv = f.inv_diagonal.data();
#define CLOTH_SIM_CASE(W)                                                   \
  case W:                                                                   \
    if (kForward) forwardSupernode<W>(c0, rows, count, block, inv, x);      \
    else backwardSupernode<W>(c0, rows, count, block, inv, x);              \
    break;
  switch (w) {
    CLOTH_SIM_CASE(1)
    CLOTH_SIM_CASE(2)
    CLOTH_SIM_CASE(3)
    CLOTH_SIM_CASE(4)
    CLOTH_SIM_CASE(5)
    CLOTH_SIM_CASE(6)
    CLOTH_SIM_CASE(7)
    CLOTH_SIM_CASE(8)
  }
#undef CLOTH_SIM_CASE
}

}  // namespace

long SupernodalFactor::solveBytes() const {
  const long per_direction = static_cast<long>(sizeof(double) * values.size() +
                                               sizeof(int) * rows.size() +
                                               sizeof(double) * inv_diagonal.size());
  return 2 * per_direction;
}

SupernodalFactor makeSupernodal(const LowerFactor& l, int max_width) {
  if (max_width < 1 || max_width > kMaxSupernode) {
    throw std::invalid_argument("makeSupernodal: max_width must be in [1, kMaxSupernode]");
  }
  SupernodalFactor f;
  f.size = l.size;
  f.inv_diagonal = l.inv_diagonal;
  f.permutation = l.permutation;
  auto count = [&](int j) { return l.col_start[j + 1] - l.col_start[j]; };
  int j = 0;
  f.row_start.push_back(0);
  f.value_start.push_back(0);
  while (j < l.size) {
    // Extend while column e-1's rows are {e} followed by exactly column e's rows.
    int e = j + 1;
    while (e < l.size && e - j < max_width && count(e - 1) == count(e) + 1 &&
           l.col_row[l.col_start[e - 1]] == e) {
      ++e;
    }
    const int w = e - j;
    f.first_column.push_back(j);
    const int below = l.col_start[e - 1];
    const int count_below = count(e - 1);
    f.rows.insert(f.rows.end(), l.col_row.begin() + below, l.col_row.begin() + below + count_below);
    f.row_start.push_back(static_cast<int>(f.rows.size()));
    const std::size_t base = f.values.size();
    f.values.resize(base + w * w + static_cast<std::size_t>(count_below) * w, 0.0);
    for (int c = 0; c < w; ++c) {
      // Column j + c: rows j + c + 1 .. e - 1 (diagonal block), then the shared row list.
      int k = l.col_start[j + c];
      for (int r = c + 1; r < w; ++r, ++k) f.values[base + r * w + c] = l.col_value[k];
      for (int i = 0; i < count_below; ++i, ++k) {
        f.values[base + w * w + static_cast<std::size_t>(i) * w + c] = l.col_value[k];
      }
    }
    f.value_start.push_back(f.values.size());
    j = e;
  }
  f.first_column.push_back(l.size);
  return f;
}

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define CLOTH_SIM_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define CLOTH_SIM_CLONES
#endif

CLOTH_SIM_CLONES void forwardSolve3(const SupernodalFactor& f, double* x) {
  for (int s = 0; s < f.supernodeCount(); ++s) solveSupernode<true>(f, s, x);
}

CLOTH_SIM_CLONES void backwardSolve3(const SupernodalFactor& f, double* x) {
  for (int s = f.supernodeCount() - 1; s >= 0; --s) solveSupernode<false>(f, s, x);
}

}  // namespace cloth_sim
