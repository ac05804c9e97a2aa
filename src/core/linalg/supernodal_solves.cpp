#include "cloth_sim/core/linalg/supernodal_solves.h"

#include <algorithm>
#include <stdexcept>

#include "cloth_sim/core/linalg/parallel.h"

// The vector type below never crosses this file's interface (only pointers do), so the ABI note
// GCC gives for 32-byte vectors in a build without AVX does not apply.
#pragma GCC diagnostic ignored "-Wpsabi"

namespace cloth_sim {
namespace {

// One node (x, y, z, pad) as a GCC/Clang vector: in double 2 SSE2 operations in the portable
// build, one AVX2 operation in the x86-64-v3 clone picked at load time (CLOTH_SIM_CLONES below);
// in float one SSE operation.
template <typename Real>
struct NodeOf;
template <>
struct NodeOf<double> {
  typedef double Type __attribute__((vector_size(32), aligned(8)));
};
template <>
struct NodeOf<float> {
  typedef float Type __attribute__((vector_size(16), aligned(4)));
};

// Everything below is forced inline into the clones of the task functions, so it is compiled
// once per target (a plain call would run the portable code in both).
#define CLOTH_SIM_INLINE inline __attribute__((always_inline))

template <typename Real>
CLOTH_SIM_INLINE typename NodeOf<Real>::Type load(const Real* p) {
  return *reinterpret_cast<const typename NodeOf<Real>::Type*>(p);
}
template <typename Real>
CLOTH_SIM_INLINE void store(Real* p, typename NodeOf<Real>::Type v) {
  *reinterpret_cast<typename NodeOf<Real>::Type*>(p) = v;
}
template <typename Real>
CLOTH_SIM_INLINE Real* node(Real* x, int k) { return x + kNodeStride * k; }

/// Forward step of one supernode of width W starting at column c0: its rows [0, own) are rows
/// of @p x, the others slots of @p slots.
template <int W, typename Real>
CLOTH_SIM_INLINE void forwardSupernode(int c0, const int* rows, int own, int count,
                                       const Real* block, const Real* inv, Real* x, Real* slots) {
  using Node = typename NodeOf<Real>::Type;
  Node xc[W];
  for (int c = 0; c < W; ++c) {  // the dense diagonal block, column by column
    Node acc = load(node(x, c0 + c));
    for (int p = 0; p < c; ++p) acc -= block[c * W + p] * xc[p];
    xc[c] = acc * inv[c0 + c];
    store(node(x, c0 + c), xc[c]);
  }
  const Real* v = block + W * W;
  for (int i = 0; i < count; ++i, v += W) {  // each row below: x_r -= sum_c L_rc x_c
    Real* xr = node(i < own ? x : slots, rows[i]);
    Node acc = load(xr);
    for (int c = 0; c < W; ++c) acc -= v[c] * xc[c];
    store(xr, acc);
  }
}

/// acc[u][c] += L_rc x_r over rows [begin, end) of one supernode, read from @p base.
template <int W, int U, typename Real>
CLOTH_SIM_INLINE void accumulateRows(typename NodeOf<Real>::Type (&acc)[U][W], const Real* v,
                                     const int* rows, int begin, int end, const Real* base) {
  using Node = typename NodeOf<Real>::Type;
  int i = begin;
  for (; i + U <= end; i += U) {
    for (int u = 0; u < U; ++u) {
      const Node xr = load(base + kNodeStride * rows[i + u]);
      for (int c = 0; c < W; ++c) acc[u][c] += v[(i + u) * W + c] * xr;
    }
  }
  for (; i < end; ++i) {
    const Node xr = load(base + kNodeStride * rows[i]);
    for (int c = 0; c < W; ++c) acc[0][c] += v[i * W + c] * xr;
  }
}

/// Backward step of one supernode of width W starting at column c0 (rows as forwardSupernode).
template <int W, typename Real>
CLOTH_SIM_INLINE void backwardSupernode(int c0, const int* rows, int own, int count,
                                        const Real* block, const Real* inv, Real* x,
                                        const Real* slots) {
  using Node = typename NodeOf<Real>::Type;
  // U rows per round so that U * W >= 8 chains of multiply-adds are in flight.
  constexpr int U = W >= 8 ? 1 : (W >= 4 ? 2 : (W >= 2 ? 4 : 8));
  Node acc[U][W] = {};
  const Real* v = block + W * W;
  accumulateRows<W, U, Real>(acc, v, rows, 0, own, x);
  accumulateRows<W, U, Real>(acc, v, rows, own, count, slots);
  for (int c = W - 1; c >= 0; --c) {  // the diagonal block, transposed, last column first
    Node sum = acc[0][c];
    for (int u = 1; u < U; ++u) sum += acc[u][c];
    Node value = load(node(x, c0 + c)) - sum;
    for (int p = c + 1; p < W; ++p) value -= block[p * W + c] * load(node(x, c0 + p));
    store(node(x, c0 + c), value * inv[c0 + c]);
  }
}

template <bool kForward, typename Real>
CLOTH_SIM_INLINE void solveSupernode(const SupernodalFactorT<Real>& f, int s, Real* x,
                                     Real* slots) {
  const int c0 = f.first_column[s], w = f.first_column[s + 1] - c0;
  const int* rows = f.rows.data() + f.row_start[s];
  const int count = f.row_start[s + 1] - f.row_start[s];
  const int own = f.own_count[s];
  const Real* block = f.values.data() + f.value_start[s];
  const Real* inv = f.inv_diagonal.data();
#define CLOTH_SIM_CASE(W)                                                          \
  case W:                                                                          \
    if (kForward) forwardSupernode<W, Real>(c0, rows, own, count, block, inv, x, slots); \
    else backwardSupernode<W, Real>(c0, rows, own, count, block, inv, x, slots);   \
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

/// Forward part of task @p t (every supernode when @p t < 0: the unsplit factor).
template <typename Real>
CLOTH_SIM_INLINE void forwardTaskImpl(const SupernodalFactorT<Real>& f, int t, Real* x) {
  Real* slots = f.scratch.data();
  if (t < 0) {
    for (int s = 0; s < f.supernodeCount(); ++s) solveSupernode<true>(f, s, x, slots);
    return;
  }
  const SolveTasks::Task& task = f.tasks.tasks[t];
  std::fill(slots + kNodeStride * task.slot_begin,
            slots + kNodeStride * (task.slot_begin + task.slot_row.size()), Real(0));
  for (std::size_t k = 0; k < task.gather_row.size(); ++k) {  // descendants' updates, in order
    Real* xr = node(x, task.gather_row[k]);
    store(xr, load(xr) + load(node(slots, task.gather_slot[k])));
  }
  for (int s : task.supernodes) solveSupernode<true>(f, s, x, slots);
}

/// Backward part of task @p t (every supernode when @p t < 0).
template <typename Real>
CLOTH_SIM_INLINE void backwardTaskImpl(const SupernodalFactorT<Real>& f, int t, Real* x) {
  Real* slots = f.scratch.data();
  if (t < 0) {
    for (int s = f.supernodeCount() - 1; s >= 0; --s) solveSupernode<false>(f, s, x, slots);
    return;
  }
  const SolveTasks::Task& task = f.tasks.tasks[t];
  for (std::size_t k = 0; k < task.slot_row.size(); ++k) {  // the ancestors' final values
    store(node(slots, task.slot_begin + static_cast<int>(k)), load(node(x, task.slot_row[k])));
  }
  for (auto s = task.supernodes.rbegin(); s != task.supernodes.rend(); ++s) {
    solveSupernode<false>(f, *s, x, slots);
  }
}

}  // namespace

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
  for (int k = 0; k < f.supernodeCount(); ++k) f.own_count.push_back(f.row_start[k + 1] - f.row_start[k]);
  return f;
}

SupernodalFactorF toSinglePrecision(const SupernodalFactor& d) {
  SupernodalFactorF f;
  f.size = d.size;
  f.first_column = d.first_column;
  f.row_start = d.row_start;
  f.rows = d.rows;
  f.own_count = d.own_count;
  f.value_start = d.value_start;
  f.values.assign(d.values.begin(), d.values.end());
  f.inv_diagonal.assign(d.inv_diagonal.begin(), d.inv_diagonal.end());
  f.permutation = d.permutation;
  f.tasks = d.tasks;
  f.scratch.assign(d.scratch.size(), 0.0f);
  return f;
}

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define CLOTH_SIM_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define CLOTH_SIM_CLONES
#endif

// The task functions, one clone per target; the phases' threads call them (parallelFor).
CLOTH_SIM_CLONES void forwardTask(const SupernodalFactor& f, int t, double* x) {
  forwardTaskImpl(f, t, x);
}
CLOTH_SIM_CLONES void backwardTask(const SupernodalFactor& f, int t, double* x) {
  backwardTaskImpl(f, t, x);
}
CLOTH_SIM_CLONES void forwardTask(const SupernodalFactorF& f, int t, float* x) {
  forwardTaskImpl(f, t, x);
}
CLOTH_SIM_CLONES void backwardTask(const SupernodalFactorF& f, int t, float* x) {
  backwardTaskImpl(f, t, x);
}

namespace {

template <typename Real>
void forwardPhases(const SupernodalFactorT<Real>& f, Real* x, int threads) {
  if (f.tasks.tasks.empty()) return forwardTask(f, -1, x);
  const SolveTasks::Schedule& plan = f.tasks.schedule(threads);
  parallelFor(threads, static_cast<int>(plan.groups.size()), [&](int g) {
    for (int t : plan.groups[g]) forwardTask(f, t, x);
  }, 2);
  for (const std::vector<int>& phase : plan.top) {
    parallelFor(threads, static_cast<int>(phase.size()), [&](int k) { forwardTask(f, phase[k], x); }, 2);
  }
}

template <typename Real>
void backwardPhases(const SupernodalFactorT<Real>& f, Real* x, int threads) {
  if (f.tasks.tasks.empty()) return backwardTask(f, -1, x);
  const SolveTasks::Schedule& plan = f.tasks.schedule(threads);
  for (auto phase = plan.top.rbegin(); phase != plan.top.rend(); ++phase) {
    parallelFor(threads, static_cast<int>(phase->size()),
                [&](int k) { backwardTask(f, (*phase)[k], x); }, 2);
  }
  parallelFor(threads, static_cast<int>(plan.groups.size()), [&](int g) {
    const std::vector<int>& group = plan.groups[g];
    for (auto t = group.rbegin(); t != group.rend(); ++t) backwardTask(f, *t, x);
  }, 2);
}

}  // namespace

void forwardSolve3(const SupernodalFactor& f, double* x, int threads) { forwardPhases(f, x, threads); }
void backwardSolve3(const SupernodalFactor& f, double* x, int threads) { backwardPhases(f, x, threads); }
void forwardSolve3(const SupernodalFactorF& f, float* x, int threads) { forwardPhases(f, x, threads); }
void backwardSolve3(const SupernodalFactorF& f, float* x, int threads) { backwardPhases(f, x, threads); }

}  // namespace cloth_sim
